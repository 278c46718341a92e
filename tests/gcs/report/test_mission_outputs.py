import json
import xml.etree.ElementTree as ET
from datetime import datetime, timezone

import numpy as np
import pytest
from PIL import Image

from comms.frames import GeodeticHome
from gcs.metrics.synthetic_record import synthetic_circle_record
from gcs.report import lonlat_to_ring, write_mission_outputs
from gcs.report.animation import frame_indices, polygon_at

HOME = GeodeticHome()


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    record, flood = synthetic_circle_record(loss_at_s=40.0, seed=2)
    out = tmp_path_factory.mktemp("run")
    start = datetime(2026, 5, 1, 12, 0, 0, tzinfo=timezone.utc)
    return record, write_mission_outputs(record, flood, "circle", HOME, out, 60.0, start_utc=start)


def test_every_output_is_written(outputs) -> None:
    _, paths = outputs
    assert set(paths) == {"metrics", "geojson", "kml", "trajectories", "animation"}
    for path in paths.values():
        assert path.exists() and path.stat().st_size > 1000


def test_metrics_json_and_polygon_files_agree_with_the_record(outputs) -> None:
    record, paths = outputs
    metrics = json.loads(paths["metrics"].read_text())
    assert metrics["summary"]["polygon_iou_final"] >= 0.97
    collection = json.loads(paths["geojson"].read_text())
    assert collection["type"] == "FeatureCollection"
    assert len(collection["features"]) == len(record.polygons)
    last = collection["features"][-1]
    assert last["properties"]["t_s"] == pytest.approx(record.polygons[-1].t_s)
    assert last["properties"]["time"].startswith("2026-05-01T12:01:00")
    ring = lonlat_to_ring(last["geometry"]["coordinates"][0], HOME)
    assert np.max(np.abs(ring - record.polygons[-1].ring_en_m)) < 0.01
    placemarks = ET.parse(paths["kml"]).getroot().findall(".//{http://www.opengis.net/kml/2.2}Placemark")
    assert len(placemarks) == len(record.polygons)


def test_pictures_are_real_images_with_content(outputs) -> None:
    _, paths = outputs
    png = Image.open(paths["trajectories"])
    assert png.format == "PNG" and png.width >= 800 and png.height >= 600
    pixels = np.asarray(png.convert("RGB")).reshape(-1, 3)
    assert len(np.unique(pixels, axis=0)) > 50  # traces, flood, legend: not a blank canvas
    gif = Image.open(paths["animation"])
    assert gif.format == "GIF" and 10 <= gif.n_frames <= 60
    gif.seek(0)
    first = np.asarray(gif.convert("RGB")).copy()
    gif.seek(gif.n_frames - 1)
    last = np.asarray(gif.convert("RGB"))
    assert np.mean(np.any(first != last, axis=-1)) > 0.01  # the flood and the drones move


def test_frame_selection_and_polygon_lookup() -> None:
    assert frame_indices(601, 60)[-1] == 600 and len(frame_indices(601, 60)) == 60
    assert list(frame_indices(3, 60)) == [0, 1, 2]
    record, _ = synthetic_circle_record(duration_s=4.0, polygon_period_s=1.0)
    assert polygon_at(record.polygons, -1.0) is None
    assert polygon_at(record.polygons, 2.5).t_s == pytest.approx(2.0)


def test_a_run_without_polygons_still_writes_valid_files(tmp_path) -> None:
    record, flood = synthetic_circle_record(duration_s=2.0, polygon_period_s=1.0)
    record.polygons = []
    paths = write_mission_outputs(record, flood, "circle", HOME, tmp_path, 60.0, animation=False)
    assert json.loads(paths["geojson"].read_text())["features"] == []
    ET.parse(paths["kml"])
    assert "animation" not in paths and paths["trajectories"].exists()
