"""Render and perceive CPU per frame, one checkout against another in the same session (before/after ratios that
hold on a loaded machine).

    .venv/bin/python bench/render_perceive_ab.py --before /tmp/main_tree [--after .] [--frames 300] [--rounds 2]
    git archive main | tar -x -C /tmp/main_tree      # a checkout of the code before

Each round runs one child process per checkout, alternating (before, after, before, after, ...); a child puts its
checkout first on ``sys.path``, sets OpenCV to one thread (as the agents, the sim bridge and the campaign workers
run it: CPU time of the calling thread is then the whole cost) and times, on the same poses for both checkouts
(within 6 m of the true edge, 10 m, random yaw, seed 5): the render and the perception of clean frames of
``circle`` and of the three hydro scenarios, and of ``circle`` frames under the ``moderate`` preset's imaging keys
with clear water (the blue cue decides), with turbid water (the grey-water cue decides) and under ``rough``.
Figures are the thread CPU time p50 [ms]; render + perceive is the p50 of the per-frame sum.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

CASES = (("circle", "clean"), ("breach", "clean"), ("river", "clean"), ("pluvial", "clean"),
         ("circle", "moderate"), ("circle", "moderate, turbid water"), ("circle", "rough"))


def child(tree: Path, frames: int) -> dict[str, list[float]]:
    """Timings of one checkout: case -> [render, perceive, render + perceive] CPU p50 [ms]."""
    sys.path.insert(0, str(tree.resolve()))
    import cv2
    import numpy as np

    cv2.setNumThreads(1)
    from bench.camera_perception import flood_named, height_m, poses
    from bench.perception_conditions import MODERATE, MODERATE_TURBID, ROUGH
    from mission_plan.imaging import ImagingSpec
    from mock_autopilot.camera.model import CameraModel
    from mock_autopilot.camera.render import CameraPose, render_frame
    from vehicle_agents.perception.segmentation import perceive

    imaging = {"clean": ImagingSpec(), "moderate": MODERATE, "moderate, turbid water": MODERATE_TURBID, "rough": ROUGH}
    camera = CameraModel()
    out: dict[str, list[float]] = {}
    for flood_name, label in CASES:
        flood = flood_named(flood_name, seed=1)
        plan = poses(flood, frames, 10.0, seed=5)
        spec = imaging[label]
        pose = CameraPose(vehicle_id=2, velocity_en_mps=(3.0, 1.0), wind_en_mps=(5.0, 0.0))
        render_frame(flood, plan[0][0], plan[0][1], plan[0][2], camera, 1, pose=pose, imaging=spec)
        render_s, perceive_s = [], []
        for t_s, position, yaw in plan:
            a = time.thread_time()
            frame = render_frame(flood, t_s, position, yaw, camera, 1, pose=pose, imaging=spec)
            b = time.thread_time()
            perceive(frame.image_bgr, height_m(flood, position), camera.fov_deg, yaw)
            render_s.append(b - a)
            perceive_s.append(time.thread_time() - b)
        both = np.add(render_s, perceive_s)
        out[f"{flood_name} | {label}"] = [float(np.median(v)) * 1e3 for v in (render_s, perceive_s, both)]
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", type=Path, help="checkout of the code before")
    parser.add_argument("--after", type=Path, default=Path(__file__).resolve().parents[1])
    parser.add_argument("--frames", type=int, default=300)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--child", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(child(args.child, args.frames)))
        return
    if args.before is None:
        parser.error("--before: a checkout of the code before is needed")
    runs: dict[str, list[dict[str, list[float]]]] = {"before": [], "after": []}
    for _ in range(args.rounds):
        for label, tree in (("before", args.before), ("after", args.after)):
            done = subprocess.run([sys.executable, __file__, "--child", str(tree), "--frames", str(args.frames)],
                                  capture_output=True, text=True, check=True, cwd=tree)
            runs[label].append(json.loads(done.stdout.strip().splitlines()[-1]))
            print(f"{label} round done, load average {os.getloadavg()[0]:.1f}", file=sys.stderr, flush=True)
    print("| flood | imaging | before: render / perceive / both [ms] | after: render / perceive / both [ms] "
          "| after / before (both) |\n|---|---|---|---|---|")
    for case in runs["before"][0]:
        cells = []
        for label in ("before", "after"):
            cells.append(", ".join(" / ".join(f"{v:.2f}" for v in run[case]) for run in runs[label]))
        ratio = [a[case][2] / b[case][2] for a, b in zip(runs["after"], runs["before"])]
        print(f"| {case} | {cells[0]} | {cells[1]} | {', '.join(f'{r:.2f}' for r in ratio)} |")


if __name__ == "__main__":
    main()
