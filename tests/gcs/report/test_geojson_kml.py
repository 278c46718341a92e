import json
import math
import xml.etree.ElementTree as ET
from datetime import datetime, timezone

import numpy as np
import pytest

from comms.frames import GeodeticHome
from gcs.polygon import signed_area_m2
from gcs.report import PolygonLog, feature_collection, lonlat_to_ring, polygon_feature, ring_to_lonlat, utc_iso

HOME = GeodeticHome(lat_deg=47.397742, lon_deg=8.545594, alt_m=488.0)
START = datetime(2026, 5, 1, 12, 0, 0, tzinfo=timezone.utc)
KML_NS = "{http://www.opengis.net/kml/2.2}"


def circle_ring(radius_m: float = 16.0, n: int = 64, clockwise: bool = False) -> np.ndarray:
    theta = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    ring = np.stack([radius_m * np.cos(theta) + 3.0, radius_m * np.sin(theta) - 2.0], axis=-1)
    return ring[::-1] if clockwise else ring


def test_rings_become_closed_ccw_lon_lat_and_round_trip_within_a_centimetre() -> None:
    ring = circle_ring(clockwise=True)
    coords = ring_to_lonlat(ring, HOME)
    assert coords[0] == coords[-1] and len(coords) == len(ring) + 1
    lonlat = np.array(coords)
    assert signed_area_m2(lonlat[:-1]) > 0.0  # counter-clockwise in [lon, lat]
    assert np.all(np.abs(lonlat[:, 0] - HOME.lon_deg) < 0.001)  # first member is longitude
    assert np.all(np.abs(lonlat[:, 1] - HOME.lat_deg) < 0.001)
    back = lonlat_to_ring(coords, HOME)
    ccw = ring[::-1]
    assert np.max(np.linalg.norm(back - ccw, axis=1)) < 0.01


def test_a_feature_has_polygon_geometry_and_time_area_properties() -> None:
    feature = polygon_feature(circle_ring(), 12.5, HOME, START, {"iou": float("nan"), "n": 3})
    assert feature is not None
    assert feature["type"] == "Feature" and feature["geometry"]["type"] == "Polygon"
    props = feature["properties"]
    assert props["t_s"] == 12.5 and props["time"] == "2026-05-01T12:00:12.500Z"
    assert props["area_m2"] == pytest.approx(math.pi * 16**2, rel=0.01)
    assert props["iou"] is None and props["n"] == 3
    assert polygon_feature(np.zeros((2, 2)), 0.0, HOME, START) is None
    collection = feature_collection([feature])
    assert json.loads(json.dumps(collection, allow_nan=False))["type"] == "FeatureCollection"
    assert utc_iso(START, 0.0001) == "2026-05-01T12:00:00.000Z"


def test_the_live_log_is_a_valid_document_after_every_append(tmp_path) -> None:
    log = PolygonLog(tmp_path, HOME, start_utc=START, name="test <&> run")
    try:
        assert json.loads(log.geojson_path.read_text())["features"] == []
        ET.parse(log.kml_path)
        for k in range(5):
            assert log.append(float(k), circle_ring(12.0 + k))
            collection = json.loads(log.geojson_path.read_text())
            assert [f["properties"]["t_s"] for f in collection["features"]] == list(range(k + 1))
            placemarks = ET.parse(log.kml_path).getroot().findall(f".//{KML_NS}Placemark")
            assert len(placemarks) == k + 1
        assert not log.append(5.0, np.zeros((0, 2)))
        assert log.count == 5
    finally:
        log.close()
    # The file is still complete without an explicit "finish" step: a crash after any append leaves it valid.
    collection = json.loads(log.geojson_path.read_text())
    assert collection["properties"]["home"]["lat_deg"] == HOME.lat_deg
    for feature in collection["features"]:
        ring = feature["geometry"]["coordinates"][0]
        assert ring[0] == ring[-1]
        assert signed_area_m2(np.array(ring)[:-1]) > 0.0


def test_kml_placemarks_carry_timestamps_and_lon_lat_coordinates(tmp_path) -> None:
    with PolygonLog(tmp_path, HOME, start_utc=START) as log:
        log.append(30.0, circle_ring())
    root = ET.parse(log.kml_path).getroot()
    assert root.tag == f"{KML_NS}kml"
    when = root.find(f".//{KML_NS}TimeStamp/{KML_NS}when")
    assert when is not None and when.text == "2026-05-01T12:00:30.000Z"
    text = root.find(f".//{KML_NS}coordinates").text
    tuples = [tuple(map(float, item.split(","))) for item in text.split()]
    assert tuples[0] == tuples[-1]
    lon, lat, alt = tuples[0]
    assert abs(lon - HOME.lon_deg) < 0.001 and abs(lat - HOME.lat_deg) < 0.001 and alt == 0.0


def test_a_process_that_dies_mid_mission_leaves_parseable_files(tmp_path) -> None:
    import os
    import subprocess
    import sys
    from pathlib import Path

    repo = Path(__file__).resolve().parents[3]
    script = (
        "import os, numpy as np\n"
        "from comms.frames import GeodeticHome\n"
        "from gcs.report import PolygonLog\n"
        f"log = PolygonLog({str(tmp_path)!r}, GeodeticHome())\n"
        "theta = np.linspace(0, 2 * np.pi, 40, endpoint=False)\n"
        "for k in range(3):\n"
        "    log.append(float(k), np.stack([10 * np.cos(theta), 10 * np.sin(theta)], axis=-1))\n"
        "os._exit(9)  # no close(), no interpreter shutdown: a crash\n"
    )
    proc = subprocess.run([sys.executable, "-c", script], cwd=repo, env={**os.environ, "PYTHONPATH": str(repo)}, timeout=60)
    assert proc.returncode == 9
    assert len(json.loads((tmp_path / "polygons.geojson").read_text())["features"]) == 3
    assert len(ET.parse(tmp_path / "polygons.kml").getroot().findall(f".//{KML_NS}Placemark")) == 3
