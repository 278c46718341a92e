"""Everything a run leaves in its output folder (SPEC §6), written from one MissionRecord.

Order matters when something goes wrong: metrics.json first (the numbers), then the georeferenced polygons (what
the rescue centre needs), then the pictures. Each file is complete once written; a failure in a later one leaves
the earlier ones in place.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from datetime import datetime, timedelta, timezone
from pathlib import Path
from typing import Any

from comms.frames import GeodeticHome
from gcs.metrics.mission import compute_mission_metrics
from gcs.mission_record import MissionRecord
from gcs.polygon.growth import area_growth_rate_m2ps
from gcs.polygon.ring import ring_area_m2
from gcs.report.animation import write_animation
from gcs.report.polygon_log import PolygonLog
from gcs.report.trajectories import plot_trajectories
from mock_autopilot.world.flood_model import FloodModel

METRICS_NAME = "metrics.json"
TRAJECTORIES_NAME = "trajectories.png"
ANIMATION_NAME = "animation.gif"
GROWTH_WINDOW_S = 5.0


def write_metrics_json(metrics: Mapping[str, Any], out_path: str | os.PathLike[str]) -> Path:
    """metrics.json, written to a temporary name and renamed, so a reader never sees half a file."""
    out = Path(out_path)
    tmp = out.with_suffix(out.suffix + ".tmp")
    tmp.write_text(json.dumps(metrics, indent=1, allow_nan=False) + "\n")
    os.replace(tmp, out)
    return out


def write_polygon_files(
    record: MissionRecord, home: GeodeticHome, out_dir: str | os.PathLike[str], scenario_name: str, start_utc: datetime
) -> tuple[Path, Path]:
    """polygons.geojson and polygons.kml: one feature / placemark per polygon sample of the record."""
    with PolygonLog(out_dir, home, name=f"FloodWatch {scenario_name}: caged flood polygon", start_utc=start_utc) as log:
        times = [sample.t_s for sample in record.polygons]
        areas = [ring_area_m2(sample.ring_en_m) for sample in record.polygons]
        for k, sample in enumerate(record.polygons):
            growth = area_growth_rate_m2ps(times[: k + 1], areas[: k + 1], window_s=GROWTH_WINDOW_S)
            log.append(sample.t_s, sample.ring_en_m, {"scenario": scenario_name, "growth_rate_m2_per_s": round(growth, 3)})
        return log.geojson_path, log.kml_path


def write_mission_outputs(
    record: MissionRecord,
    flood: FloodModel,
    scenario_name: str,
    home: GeodeticHome,
    out_dir: str | os.PathLike[str],
    fov_deg: float,
    *,
    start_utc: datetime | None = None,
    metrics: Mapping[str, Any] | None = None,
    animation: bool = True,
    max_frames: int = 60,
) -> dict[str, Path]:
    """Write metrics.json, polygons.geojson, polygons.kml, trajectories.png and animation.gif into ``out_dir``.

    ``start_utc``: wall-clock time of flood time 0 for the timestamps (default: now minus the record's length).
    ``metrics``: reuse an already computed ``compute_mission_metrics`` result. Returns {name: path}.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if start_utc is None:
        last_t = float(record.t_s[-1]) if len(record.t_s) else 0.0
        start_utc = datetime.now(timezone.utc) - timedelta(seconds=last_t)
    paths: dict[str, Path] = {}
    metrics = metrics if metrics is not None else compute_mission_metrics(record, flood, fov_deg)
    paths["metrics"] = write_metrics_json(metrics, out / METRICS_NAME)
    paths["geojson"], paths["kml"] = write_polygon_files(record, home, out, scenario_name, start_utc)
    if len(record.t_s):
        paths["trajectories"] = plot_trajectories(record, flood, out / TRAJECTORIES_NAME, title=_title(record, scenario_name))
        if animation:
            paths["animation"] = write_animation(record, flood, out / ANIMATION_NAME, metrics=metrics, max_frames=max_frames)
    return paths


def _title(record: MissionRecord, scenario_name: str) -> str:
    return f"{scenario_name}: UAV traces ({record.mode} mode, {record.engine} engine, seed {record.seed})"
