"""Benchmark: camera render + onboard perception per frame (p50/p99), per flood model and image size, and the
accuracy of perception against the renderer's truth (the figures quoted in docs/PERCEPTION.md).

    .venv/bin/python -m bench.camera_perception [--frames 2000] [--sizes 128x128,160x120] [--accuracy 300]

Timing: each call is timed alone, wall clock (``time.perf_counter``: a loaded machine shows in p99, when the
process waits for a core) and CPU time of the thread (``time.thread_time``: the work itself); poses
are random points within 6 m of the flood's true edge at a random time and yaw, as the boundary drones see it.
Cold costs are reported separately: building the flood model (the terrain's spill levels) and the first frame of
a new seed (texture tiles).
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import os
import platform
import subprocess
import time
from typing import Any

import cv2
import numpy as np

from mock_autopilot.camera.appearance import ground_textures
from mock_autopilot.camera.model import CameraModel
from gcs.scenario import load_scenario
from mock_autopilot.camera.render import MIN_ALTITUDE_M, render_frame
from mock_autopilot.camera.truth import ACCURACY_FLOODS, median_distance_to_shore_m, truth_reference
from mock_autopilot.world.config import flood_model_from_config
from mock_autopilot.world.flood_model import FloodModel
from mock_autopilot.world.ground import height_above_ground_m
from vehicle_agents.perception.segmentation import MIN_CLASS_FRACTION, perceive
from vehicle_agents.perception.water_mask import segment_water

Pose = tuple[float, tuple[float, float, float], float]
"""(flood time [s], position [m; ENU], PX4 yaw [rad])."""


def poses(flood: FloodModel, n: int, altitude_m: float, seed: int) -> list[Pose]:
    """(t, position, yaw) within 6 m of a random point of the true edge."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        t_s = float(rng.uniform(0.0, 60.0))
        ring = flood.boundary_en_m(t_s)
        edge = ring[rng.integers(len(ring))]
        out.append((t_s, (float(edge[0] + rng.uniform(-6, 6)), float(edge[1] + rng.uniform(-6, 6)), altitude_m),
                    float(rng.uniform(-math.pi, math.pi))))
    return out


def flood_named(name: str, seed: int) -> FloodModel:
    """A flood of :data:`ACCURACY_FLOODS`, or a bundled scenario's own flood (``breach``, ``river``, ``pluvial``)."""
    if name in ACCURACY_FLOODS:
        return flood_model_from_config(ACCURACY_FLOODS[name], seed=seed)
    scenario = load_scenario(name)
    return flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)


def height_m(flood: FloodModel, position: tuple[float, float, float]) -> float:
    """What the rangefinder reads, which perception scales by (the altitude over flat ground)."""
    return max(height_above_ground_m(flood, position), MIN_ALTITUDE_M)


def percentiles_ms(samples_s: list[float]) -> dict[str, float]:
    a = np.asarray(samples_s) * 1e3
    return {"p50": round(float(np.percentile(a, 50)), 3), "p99": round(float(np.percentile(a, 99)), 3),
            "mean": round(float(a.mean()), 3)}


def time_model(name: str, camera: CameraModel, frames: int) -> dict[str, Any]:
    t0 = time.perf_counter()
    flood = flood_named(name, seed=1)
    build_s = time.perf_counter() - t0
    plan = poses(flood, frames, 10.0, seed=5)
    render_frame(flood, plan[0][0], plan[0][1], plan[0][2], camera, 1)  # warm caches (textures, noise bank)
    render_s, perceive_s, both_s, render_cpu, perceive_cpu = [], [], [], [], []
    gc.collect()
    for t_s, position, yaw in plan:
        a, ca = time.perf_counter(), time.thread_time()
        frame = render_frame(flood, t_s, position, yaw, camera, 1)
        b, cb = time.perf_counter(), time.thread_time()
        perceive(frame.image_bgr, height_m(flood, position), camera.fov_deg, yaw)
        c, cc = time.perf_counter(), time.thread_time()
        render_s.append(b - a)
        perceive_s.append(c - b)
        both_s.append(c - a)
        render_cpu.append(cb - ca)
        perceive_cpu.append(cc - cb)
    return {"model": name, "size": f"{camera.width_px}x{camera.height_px}", "build_ms": round(build_s * 1e3, 1),
            "render": percentiles_ms(render_s), "perceive": percentiles_ms(perceive_s),
            "render+perceive": percentiles_ms(both_s),
            "render_cpu": percentiles_ms(render_cpu), "perceive_cpu": percentiles_ms(perceive_cpu)}


def accuracy(name: str, frames: int, camera: CameraModel, altitude_m: float = 10.0, pose_seed: int = 11,
             appearance_seed: int = 3) -> dict[str, Any]:
    """Pooled water IoU, per-frame IoU p5, midpoint / centroid error, edge-point error, flag agreement."""
    flood = flood_named(name, seed=3)
    inter = union = 0
    ious, mid, cen, edge = [], [], [], []
    flag_errors = 0
    for t_s, position, yaw in poses(flood, frames, altitude_m, seed=pose_seed):
        frame = render_frame(flood, t_s, position, yaw, camera, appearance_seed)
        agl_m = height_m(flood, position)
        result = perceive(frame.image_bgr, agl_m, camera.fov_deg, yaw)
        truth = frame.water_mask
        mask, _, _ = segment_water(frame.image_bgr)
        mask = mask if mask is not None else np.full(truth.shape, bool(result.only_water))
        inter += int((mask & truth).sum())
        union += int((mask | truth).sum())
        fraction = float(truth.mean())
        both = 2 * MIN_CLASS_FRACTION <= fraction <= 1 - 2 * MIN_CLASS_FRACTION
        near_threshold = MIN_CLASS_FRACTION / 2 < min(fraction, 1 - fraction) < 2 * MIN_CLASS_FRACTION
        if near_threshold:
            continue
        if both != result.has_edge or (not both and result.only_water != (fraction > 0.5)):
            flag_errors += 1
            continue
        if not both:
            continue
        ious.append(float((mask & truth).sum() / (mask | truth).sum()))
        ref = truth_reference(camera, (position[0], position[1], agl_m), yaw, truth)
        mid.append(float(np.linalg.norm(result.midpoint_offset_en_m - ref.midpoint_en_m)))
        cen.append(max(float(np.linalg.norm(result.water_centroid_en_m - ref.water_centroid_en_m)),
                       float(np.linalg.norm(result.land_centroid_en_m - ref.land_centroid_en_m))))
        edge.append(median_distance_to_shore_m(result.edge_points_en_m, ref))
    return {
        "model": name, "size": f"{camera.width_px}x{camera.height_px}", "altitude_m": altitude_m,
        "frames": frames, "frames_with_edge": len(mid),
        "pooled_iou": round(inter / union, 4), "iou_p5": round(float(np.percentile(ious, 5)), 4),
        "midpoint_err_m_p95": round(float(np.percentile(mid, 95)), 3), "midpoint_err_m_max": round(max(mid), 3),
        "centroid_err_m_max": round(max(cen), 3), "edge_err_m_median": round(float(np.median(edge)), 3),
        "flag_errors": flag_errors,
    }


def machine() -> str:
    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")), "?")
    load = os.getloadavg()[0]
    return f"{os.cpu_count()} CPU ({cpu}), load average {load:.1f}, Python {platform.python_version()}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=2000, help="timed frames per model and size")
    parser.add_argument("--sizes", default="128x128,160x120", help="comma-separated WxH list")
    parser.add_argument("--models", default=",".join(ACCURACY_FLOODS),
                        help="comma-separated flood models, or bundled scenarios (breach, river, pluvial)")
    parser.add_argument("--pose-seed", type=int, default=11, help="seed of the accuracy poses")
    parser.add_argument("--appearance-seed", type=int, default=3, help="texture and sensor-noise seed for accuracy")
    parser.add_argument("--accuracy", type=int, default=0, help="also measure accuracy over this many frames")
    parser.add_argument("--json", default=None, help="write all results to this file")
    args = parser.parse_args()
    cv2.setNumThreads(1)  # as the agents and the sim bridge run it: the thread's CPU time is then the whole cost
    models = [m for m in args.models.split(",") if m]
    cameras = [CameraModel(*(int(v) for v in size.split("x"))) for size in args.sizes.split(",") if size]
    print(machine())
    t0 = time.perf_counter()
    ground_textures(12345)
    print(f"cold: texture tiles of a new seed {1e3 * (time.perf_counter() - t0):.0f} ms (once per seed)")
    results: dict[str, Any] = {"machine": machine(), "timing": [], "accuracy": []}
    print("wall-clock p50/p99 [ms] (CPU-time p50/p99 of the thread in brackets)")
    print(f"{'model':10} {'size':8} {'build ms':>8}  {'render':>28}  {'perceive':>28}  {'both (wall)':>13}")
    for camera in cameras:
        for name in models:
            r = time_model(name, camera, args.frames)
            results["timing"].append(r)
            print(f"{name:10} {r['size']:8} {r['build_ms']:8.1f}"
                  f"  {r['render']['p50']:6.3f}/{r['render']['p99']:6.3f}"
                  f" ({r['render_cpu']['p50']:5.3f}/{r['render_cpu']['p99']:5.3f})"
                  f"  {r['perceive']['p50']:6.3f}/{r['perceive']['p99']:6.3f}"
                  f" ({r['perceive_cpu']['p50']:5.3f}/{r['perceive_cpu']['p99']:5.3f})"
                  f"  {r['render+perceive']['p50']:5.3f}/{r['render+perceive']['p99']:6.3f}")
    if args.accuracy:
        print("\naccuracy at 10 m (pooled water IoU, per-frame IoU p5, midpoint error p95/max, centroid max, "
              "edge median)")
        for camera in cameras:
            for name in models:
                a = accuracy(name, args.accuracy, camera, pose_seed=args.pose_seed,
                             appearance_seed=args.appearance_seed)
                results["accuracy"].append(a)
                print(f"{name:10} {a['size']:8} IoU {a['pooled_iou']:.4f} p5 {a['iou_p5']:.4f}  midpoint "
                      f"{a['midpoint_err_m_p95']:.3f}/{a['midpoint_err_m_max']:.3f} m"
                      f"  centroid {a['centroid_err_m_max']:.3f} m  edge {a['edge_err_m_median']:.3f} m"
                      f"  flags wrong {a['flag_errors']}/{a['frames']}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(results, fh, indent=1)
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
        print(f"\ncommit {commit}")
    except OSError:
        pass


if __name__ == "__main__":
    main()
