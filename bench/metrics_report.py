"""Benchmark of the metrics and report code on scripted records (no engine needed).

Run: ``.venv/bin/python bench/metrics_report.py``. Prints wall times of ``compute_mission_metrics``,
``caged_polygon`` and ``write_mission_outputs`` for the paper's ``circle`` (13 vehicles, 60 s at 10 Hz) and a
``large``-sized record (208 vehicles: 32 boundary, 175 followers, 48 -> 64 m over 120 s at 5 Hz).
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from comms.frames import GeodeticHome  # noqa: E402
from gcs.metrics import compute_mission_metrics  # noqa: E402
from gcs.metrics.synthetic_record import synthetic_circle_record  # noqa: E402
from gcs.polygon import caged_polygon  # noqa: E402
from gcs.report import write_mission_outputs  # noqa: E402
from mission_plan.roles import Role
from mock_autopilot.world.flood_model import ExpandingCircle  # noqa: E402


def best_of(runs: int, fn) -> float:  # noqa: ANN001
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> int:
    circle, circle_flood = synthetic_circle_record(loss_at_s=40.0, seed=1)
    large, large_flood = synthetic_circle_record(
        n_boundary=32, n_followers=175, duration_s=120.0, rate_hz=5.0, follower_radius_m=40.0, spread_s=40.0,
        polygon_period_s=0.5, flood=ExpandingCircle(radius_start_m=48.0, radius_end_m=64.0, growth_duration_s=120.0),
    )
    rows = []
    for name, record, flood in (("circle (13 veh, 60 s @ 10 Hz)", circle, circle_flood),
                                ("large (208 veh, 120 s @ 5 Hz)", large, large_flood)):
        t_metrics = best_of(3, lambda: compute_mission_metrics(record, flood, 60.0))
        metrics = compute_mission_metrics(record, flood, 60.0)
        last = -1
        boundary = [i for i, r in enumerate(record.roles) if r == Role.BOUNDARY]
        positions = record.positions_enu_m[last, boundary, :2]
        rng = np.random.default_rng(0)
        edges = []
        r = flood.radius_m(float(record.t_s[last]))
        theta = np.linspace(0, 2 * np.pi, int(2 * np.pi * r / 0.1), endpoint=False)
        ring = np.stack([r * np.cos(theta), r * np.sin(theta)], axis=-1)
        for p in positions:
            inside = np.all(np.abs(ring - p) <= 5.77, axis=1)
            edges.append(ring[inside] + rng.normal(0, 0.05, (int(inside.sum()), 2)))
        t_caged = best_of(5, lambda: caged_polygon(positions, edges))
        with tempfile.TemporaryDirectory() as out:
            t_outputs = best_of(1, lambda: write_mission_outputs(record, flood, "bench", GeodeticHome(), out, 60.0, metrics=metrics))
            sizes = {p.name: p.stat().st_size // 1024 for p in Path(out).iterdir()}
        rows.append((name, t_metrics, t_caged, t_outputs, sizes, metrics["summary"]["polygon_iou_final"]))
    for name, t_metrics, t_caged, t_outputs, sizes, iou in rows:
        print(f"{name}: compute_mission_metrics {t_metrics:.2f} s; caged_polygon {1000 * t_caged:.1f} ms "
              f"(final IoU {iou:.3f}); write_mission_outputs (metrics given) {t_outputs:.2f} s; sizes kB {sizes}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
