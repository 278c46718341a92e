"""Do the renderer and the perception of this checkout give the same answers as those of another checkout? Frames
are compared byte for byte, perception results field by field (exact floats), per flood and imaging condition.

    git archive main | tar -x -C /tmp/main_tree
    .venv/bin/python -m bench.render_perceive_same --before /tmp/main_tree [--frames 40]

The before checkout's camera and perception are imported beside this checkout's as in
:mod:`bench.render_perceive_ab`. Perception is compared on the frames the before renderer drew, so a changed
renderer does not hide a changed perception. Poses: within 6 m of the true edge at 10 m (and 5 m and 25 m for
clean frames), seeds from ``bench.perception_conditions.DEV``; tilted and preset rows draw roll and pitch as that
benchmark does. Prints one row per case: frames identical, perception results identical.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from bench.camera_perception import flood_named, height_m, poses
from bench.perception_conditions import CONDITIONS, DEV
from bench.render_perceive_ab import load_before
from mock_autopilot.camera import render as after_render
from mock_autopilot.camera.model import CameraModel
from vehicle_agents.perception import segmentation as after_segmentation

GEOMETRIC = ("circle", "ellipse", "nonconvex", "drift", "terrain")
HYDRO = ("hydro", "breach", "river", "pluvial")
RESULT_FIELDS = ("has_edge", "water_fraction", "only_land", "only_water", "footprint_side_m", "midpoint_offset_en_m",
                 "water_centroid_en_m", "land_centroid_en_m", "edge_normal_en", "edge_tangent_en", "edge_points_en_m",
                 "shore_points_en_m", "water_centroid_px", "land_centroid_px", "ground_sample_m", "water_mask")


def same_value(a: Any, b: Any) -> bool:
    """Exact equality of two result fields (NaN equals NaN, arrays element by element with their shape)."""
    if a is None or b is None:
        return a is None and b is None
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return bool(np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True))
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return bool(a == b)


def same_result(a: Any, b: Any) -> bool:
    return all(same_value(getattr(a, f), getattr(b, f)) for f in RESULT_FIELDS)


def compare_case(flood_name: str, condition: str, altitude_m: float, frames: int, before: tuple[Any, Any]
                 ) -> tuple[int, int]:
    """(frames identical, perception results identical) over ``frames`` poses of one case."""
    spec, max_tilt_deg = CONDITIONS[condition]
    camera = CameraModel()
    flood = flood_named(flood_name, seed=3)
    rng = np.random.default_rng([DEV["pose"], 0xC0DE])
    same_frames = same_results = 0
    before_render, before_segmentation = before
    for k, (t_s, position, yaw) in enumerate(poses(flood, frames, altitude_m, seed=DEV["pose"])):
        seed = DEV["appearance"][k % len(DEV["appearance"])]
        speed, heading = rng.uniform(0.0, 5.0), rng.uniform(-math.pi, math.pi)
        tilt = tuple(math.radians(float(v)) for v in rng.uniform(-max_tilt_deg, max_tilt_deg, 2))
        drawn = []
        for render in (before_render, after_render):
            pose = render.CameraPose(tilt_rad=tilt, vehicle_id=k % 13 + 1,
                                     velocity_en_mps=(speed * math.cos(heading), speed * math.sin(heading)),
                                     wind_en_mps=(5.0, 0.0))
            drawn.append(render.render_frame(flood, t_s, position, yaw, camera, seed, pose=pose, imaging=spec))
        same_frames += int(np.array_equal(drawn[0].image_bgr, drawn[1].image_bgr)
                           and np.array_equal(drawn[0].water_mask, drawn[1].water_mask))
        agl = height_m(flood, position)
        results = [segmentation.perceive(drawn[0].image_bgr, agl, camera.fov_deg, yaw, roll_rad=tilt[0],
                                         pitch_rad=tilt[1])
                   for segmentation in (before_segmentation, after_segmentation)]
        same_results += int(same_result(*results))
    return same_frames, same_results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", type=Path, required=True, help="checkout of the code before")
    parser.add_argument("--frames", type=int, default=40, help="poses per case")
    parser.add_argument("--floods", default=",".join(GEOMETRIC + HYDRO))
    parser.add_argument("--conditions", default="clean,tilt,moderate,turbid_water,rough")
    args = parser.parse_args()
    cv2.setNumThreads(1)
    with tempfile.TemporaryDirectory() as scratch:
        before = load_before(args.before.resolve(), Path(scratch))
        print("| flood | condition | height [m] | frames identical | perception identical |\n|---|---|---|---|---|")
        totals = [0, 0, 0]
        for flood_name in (f for f in args.floods.split(",") if f):
            for condition in (c for c in args.conditions.split(",") if c):
                for altitude_m in ((5.0, 10.0, 25.0) if condition == "clean" else (10.0,)):
                    frames, results = compare_case(flood_name, condition, altitude_m, args.frames, before)
                    totals = [totals[0] + args.frames, totals[1] + frames, totals[2] + results]
                    print(f"| {flood_name} | {condition} | {altitude_m:g} | {frames} / {args.frames} | "
                          f"{results} / {args.frames} |", flush=True)
        print(f"total: {totals[1]} / {totals[0]} frames identical, {totals[2]} / {totals[0]} perception results "
              "identical", file=sys.stderr)


if __name__ == "__main__":
    main()
