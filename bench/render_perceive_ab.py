"""Render and perceive CPU per frame, the code before against this checkout, interleaved frame by frame in one
process (before/after ratios that hold on a loaded machine, where separate runs differ by tens of per cent).

    git archive main | tar -x -C /tmp/main_tree      # a checkout of the code before
    .venv/bin/python -m bench.render_perceive_ab --before /tmp/main_tree [--frames 300] [--floods river,circle]

The before checkout's ``mock_autopilot/camera`` and ``vehicle_agents/perception`` are copied into a scratch
directory as the packages ``before_camera`` and ``before_perception`` (their own imports of each other renamed);
everything else (flood models, projection, presets) is this checkout's, so only the camera and perception differ.
For every pose both renderers draw the frame and both perceptions read it (before, then after, then the other way
round on the next pose); each call is timed alone (thread CPU time, OpenCV on one thread as the agents run it). The
cases: clean frames of ``circle`` and of the three hydro scenarios, and ``circle`` under the ``moderate`` preset's
imaging keys with clear water (the blue cue decides), with turbid water (the grey-water cue decides) and under
``rough``. Poses within 6 m of the true edge at 10 m, random yaw (seed 5). Prints p50 [ms] and after / before.
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from bench.camera_perception import flood_named, height_m, machine, poses
from bench.perception_conditions import MODERATE, MODERATE_TURBID, ROUGH
from mission_plan.imaging import ImagingSpec
from mock_autopilot.camera import render as after_render
from mock_autopilot.camera.model import CameraModel
from vehicle_agents.perception import segmentation as after_segmentation

CASES = (("circle", "clean"), ("breach", "clean"), ("river", "clean"), ("pluvial", "clean"),
         ("circle", "moderate"), ("circle", "moderate, turbid water"), ("circle", "rough"))
IMAGING = {"clean": ImagingSpec(), "moderate": MODERATE, "moderate, turbid water": MODERATE_TURBID, "rough": ROUGH}
RENAMES = {"mock_autopilot/camera": "before_camera", "vehicle_agents/perception": "before_perception"}


def load_before(tree: Path, scratch: Path) -> tuple[Any, Any]:
    """(render module, segmentation module) of the before checkout, imported as renamed packages."""
    for source, name in RENAMES.items():
        shutil.copytree(tree / source, scratch / name)
    for path in scratch.rglob("*.py"):
        text = path.read_text()
        for source, name in RENAMES.items():
            text = re.sub(rf"\b{source.replace('/', '.')}\.", f"{name}.", text)
        path.write_text(text)
    sys.path.insert(0, str(scratch))
    return importlib.import_module("before_camera.render"), importlib.import_module("before_perception.segmentation")


def time_case(flood_name: str, label: str, frames: int, before: tuple[Any, Any]) -> dict[str, float]:
    """p50 thread CPU [ms] of render, perceive and their sum, before and after, on the same poses."""
    camera = CameraModel()
    flood = flood_named(flood_name, seed=1)
    plan = poses(flood, frames, 10.0, seed=5)
    spec = IMAGING[label]
    sides = {"before": before, "after": (after_render, after_segmentation)}
    poses_of = {name: render.CameraPose(vehicle_id=2, velocity_en_mps=(3.0, 1.0), wind_en_mps=(5.0, 0.0))
                for name, (render, _) in sides.items()}
    for name, (render, _) in sides.items():
        render.render_frame(flood, plan[0][0], plan[0][1], plan[0][2], camera, 1, pose=poses_of[name], imaging=spec)
    samples: dict[str, list[float]] = {f"{n} {k}": [] for n in sides for k in ("render", "perceive", "both")}
    for i, (t_s, position, yaw) in enumerate(plan):
        for name in (("before", "after") if i % 2 == 0 else ("after", "before")):
            render, segmentation = sides[name]
            a = time.thread_time()
            frame = render.render_frame(flood, t_s, position, yaw, camera, 1, pose=poses_of[name], imaging=spec)
            b = time.thread_time()
            segmentation.perceive(frame.image_bgr, height_m(flood, position), camera.fov_deg, yaw)
            c = time.thread_time()
            samples[f"{name} render"].append(b - a)
            samples[f"{name} perceive"].append(c - b)
            samples[f"{name} both"].append(c - a)
    return {key: float(np.median(v)) * 1e3 for key, v in samples.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", type=Path, required=True, help="checkout of the code before")
    parser.add_argument("--frames", type=int, default=300)
    parser.add_argument("--floods", default=None, help="only the cases of these floods (comma-separated)")
    args = parser.parse_args()
    cv2.setNumThreads(1)
    with tempfile.TemporaryDirectory() as scratch:
        before = load_before(args.before.resolve(), Path(scratch))
        print(f"{machine()} (start)", file=sys.stderr)
        print("| flood | imaging | render before / after | perceive before / after | render + perceive before / "
              "after | after / before (render, perceive, both) |\n|---|---|---|---|---|---|")
        floods = set(args.floods.split(",")) if args.floods else None
        for flood_name, label in (c for c in CASES if floods is None or c[0] in floods):
            r = time_case(flood_name, label, args.frames, before)
            ratios = ", ".join(f"{r['after ' + k] / r['before ' + k]:.2f}" for k in ("render", "perceive", "both"))
            print(f"| {flood_name} | {label} | {r['before render']:.2f} / {r['after render']:.2f} | "
                  f"{r['before perceive']:.2f} / {r['after perceive']:.2f} | {r['before both']:.2f} / "
                  f"{r['after both']:.2f} | {ratios} |", flush=True)
        print(f"{machine()} (end), pid {os.getpid()}", file=sys.stderr)


if __name__ == "__main__":
    main()
