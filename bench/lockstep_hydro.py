"""Benchmark: where a lockstep run's CPU goes on the hydro scenarios, beside `circle`, in one process.

Each scenario runs ``--sim`` seconds once to warm up (imports, the flood built from the cache), then again under
cProfile with the process CPU clock as its timer; the table gives the engine's CPU per simulated second, per camera
frame, and the share of the profiled CPU spent in each part: the onboard core of the whole fleet, the camera's
rendering (without the flood lookups), the flood world's lookups it makes (depth over the footprint, flow, ground
heights), perception, and the rest (radio, vehicle backend, polygon, record). cProfile's own overhead inflates every
call alike, so compare the shares and ratios, not the absolute milliseconds, with an unprofiled run.

    .venv/bin/python -m bench.lockstep_hydro [--sim 20] [--scenarios circle breach river pluvial] [--mode improved]
    .venv/bin/python -m bench.lockstep_hydro --lookups breach    # CPU per call of the flood's per-frame lookups
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import time

import cv2
import numpy as np

from gcs.lockstep.engine import run_lockstep
from gcs.scenario import load_scenario

WORLD = "mock_autopilot/world/"


def _cumulative(raw: dict, file_part: str, func: str) -> float:
    return sum(v[3] for (file, _, name), v in raw.items() if file_part in file and name == func)


def _shares(stats: pstats.Stats, total_s: float) -> dict[str, float]:
    """CPU [s] of each part. The flood's lookups are every call into ``mock_autopilot/world`` from outside it (the
    model built from the cache at the start included); those the renderer makes are taken out of its figure."""
    raw = stats.stats  # type: ignore[attr-defined]
    world = world_in_render = 0.0
    for (file, _, _), (_, _, _, _, callers) in raw.items():
        if WORLD not in file:
            continue
        for (caller_file, _, caller), timing in callers.items():
            if WORLD in caller_file:
                continue
            world += timing[3]
            if caller_file.endswith("mock_autopilot/camera/render.py") and caller == "render_frame":
                world_in_render += timing[3]
    out = {
        "onboard core": _cumulative(raw, "vehicle_agents/core/onboard.py", "onboard_step"),
        "camera render": _cumulative(raw, "mock_autopilot/camera/render.py", "render_frame") - world_in_render,
        "flood lookups": world,
        "perception": _cumulative(raw, "vehicle_agents/perception/segmentation.py", "perceive"),
    }
    out["rest"] = total_s - sum(out.values())
    return out


def lookup_costs(name: str, calls: int = 2000) -> None:
    """CPU [µs] per call of what a frame asks the flood: the rangefinder's reading, the depth raster at a flood time
    (again for the same time, as the fleet's other cameras do), depth over an 80x60 footprint, flow at the drone."""
    from mock_autopilot.world.config import flood_model_from_config
    from mock_autopilot.world.ground import height_above_ground_m

    scenario = load_scenario(name, [])
    flood = flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
    position = np.array([3.0, -20.0, 10.0])
    grid = np.zeros((60, 80, 2))
    grid[..., 0] = np.arange(80)[None, :] * 0.1
    grid[..., 1] = -np.arange(60)[:, None] * 0.1
    checks = {
        "rangefinder reading": lambda i: height_above_ground_m(flood, position),
        "depth raster, same flood time": lambda i: flood.depth_raster_m(5.0),
        "depth raster, new flood time": lambda i: flood.depth_raster_m(i * 0.01),
        "depth over the footprint": lambda i: flood.depth_on_affine_grid_m(grid, 5.0),
        "flow at the drone": lambda i: flood.flow_at_mps(position[:2], 5.0),
    }
    print(f"| {name}: lookup | CPU per call [µs] |")
    print("|---|---|")
    for label, call in checks.items():
        start = time.process_time()
        for i in range(calls):
            call(i)
        print(f"| {label} | {(time.process_time() - start) / calls * 1e6:.1f} |")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--sim", type=float, default=20.0)
    parser.add_argument("--scenarios", nargs="*", default=["circle", "breach", "river", "pluvial"])
    parser.add_argument("--mode", default="improved")
    parser.add_argument("--lookups", metavar="SCENARIO", help="only time the flood's per-frame lookups on SCENARIO")
    ns = parser.parse_args()
    cv2.setNumThreads(1)
    if ns.lookups:
        lookup_costs(ns.lookups)
        return
    names = ("onboard core", "camera render", "flood lookups", "perception", "rest")
    print(f"| scenario | vehicles | frames | engine CPU [s] (unprofiled) | CPU per sim s | CPU per frame [ms] | "
          + " | ".join(f"{n} [%]" for n in names) + " |")
    print("|" + "---|" * (6 + len(names)))
    for name in ns.scenarios:
        scenario = load_scenario(name, [])
        run_lockstep(scenario, ns.mode, duration_s=1.0)
        plain = run_lockstep(scenario, ns.mode, duration_s=ns.sim)
        profile = cProfile.Profile(time.process_time)
        profile.enable()
        run_lockstep(scenario, ns.mode, duration_s=ns.sim)
        profile.disable()
        stats = pstats.Stats(profile)
        total = stats.total_tt  # type: ignore[attr-defined]
        shares = _shares(stats, total)
        print(f"| {name} | {len(scenario.vehicles)} | {plain.frames} | {plain.cpu_s:.1f} | {plain.cpu_s / ns.sim:.2f} | "
              f"{1000 * plain.cpu_s / max(plain.frames, 1):.2f} | "
              + " | ".join(f"{100 * shares[n] / total:.0f}" for n in names) + " |", flush=True)


if __name__ == "__main__":
    main()
