"""Benchmark: wall time of `circle` in the lockstep engine (13 vehicles, 60 s simulated, camera + perception of
every vehicle at every camera frame), in both modes, plus where the time goes (render, perceive, control).

    .venv/bin/python -m bench.lockstep_circle [--repeat N] [--set key=value ...]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gcs.lockstep import engine
from gcs.scenario import load_scenario
from mission_plan.roles import Role
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.camera.render import render_frame
from vehicle_agents.perception.segmentation import perceive


def stage_costs_ms(scenario_overrides: list[str], frames: int = 200) -> dict[str, float]:
    """Mean CPU cost of one camera render and one perception at the circle's edge."""
    scenario = load_scenario("circle", scenario_overrides)
    flood = engine.flood_model_from_config(scenario.flood, seed=1)
    camera = CameraModel(scenario.camera.width_px, scenario.camera.height_px, scenario.camera.fov_deg)
    positions = [np.array([12.0 * np.cos(a), 12.0 * np.sin(a), 10.0]) for a in np.linspace(0, 6.28, frames)]
    render_frame(flood, 0.0, positions[0], 0.0, camera, 1)
    t0 = time.process_time()
    images = [render_frame(flood, 0.1 * k, p, 0.0, camera, 1).image_bgr for k, p in enumerate(positions)]
    t1 = time.process_time()
    for image in images:
        perceive(image, 10.0, camera.fov_deg, 0.0)
    t2 = time.process_time()
    return {"render_ms": (t1 - t0) / frames * 1e3, "perceive_ms": (t2 - t1) / frames * 1e3}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    parser.add_argument("--cameras", choices=("all", Role.BOUNDARY.value), default="all",
                        help="whose camera is rendered and segmented at every frame (default: every vehicle's)")
    ns = parser.parse_args()
    scenario = load_scenario("circle", ns.overrides)
    print(f"circle: {len(scenario.vehicles)} vehicles, {scenario.duration_s:.0f} s simulated, control "
          f"{scenario.control_rate_hz:g} Hz, camera {scenario.camera.width_px}x{scenario.camera.height_px} at "
          f"{scenario.camera.rate_hz:g} Hz, cameras {ns.cameras}")
    print("stage costs:", {k: round(v, 3) for k, v in stage_costs_ms(ns.overrides).items()})
    for mode in ("paper", "improved"):
        walls, cpus = [], []
        for _ in range(ns.repeat):
            result = engine.run_lockstep(scenario, mode, cameras=ns.cameras)
            walls.append(result.wall_s)
            cpus.append(result.cpu_s)
        best, cpu = min(walls), min(cpus)
        steps = result.steps + 1
        print(f"{mode}: best wall {best:.2f} s of {ns.repeat} -> {scenario.duration_s / best:.1f}x real time; "
              f"CPU {cpu:.2f} s -> {scenario.duration_s / cpu:.1f}x ({result.frames} frames, "
              f"{cpu / (steps * len(scenario.vehicles)) * 1e3:.2f} ms CPU per vehicle-step)")


if __name__ == "__main__":
    main()
