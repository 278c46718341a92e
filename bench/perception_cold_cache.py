"""What a frame's perception costs with the CPU's caches warm and cold, and at two image sizes: where the CPU of a
grey-water frame goes when it is not the pixels.

    .venv/bin/python -m bench.perception_cold_cache [--frames 300] [--rounds 3] [--sweep-mib 32]

The frames are rendered once (``circle`` at 10 m, poses within 6 m of the edge, seed 5; clean, and the ``moderate``
preset's imaging keys with turbid water, which the grey-water cue decides) and kept in memory. Each round then
times ``perceive`` on every frame (thread CPU time, OpenCV on one thread as the agents run it) four ways,
alternating frame by frame so the host's state is shared: **warm**, the frame perceived right after the previous
one; **cold**, after reading ``--sweep-mib`` of other memory (more than this CPU's caches, as an agent's other work
between two frames does: the renderer's tiles, MAVSDK, Zenoh, the control core); and both again on the same frames
shrunk to half the side (a quarter of the pixels). Prints p50 [ms] per round and case.
"""

from __future__ import annotations

import argparse
import time

import cv2
import numpy as np

from bench.camera_perception import flood_named, height_m, machine, poses
from bench.perception_conditions import MODERATE_TURBID
from mission_plan.imaging import ImagingSpec
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.camera.render import CameraPose, render_frame
from vehicle_agents.perception.segmentation import perceive

Frame = tuple[np.ndarray, float, float, float]


def rendered(spec: ImagingSpec, frames: int) -> list[Frame]:
    """(image, height above ground [m], field of view [deg], yaw [rad]) of ``frames`` poses of ``circle``."""
    camera = CameraModel()
    flood = flood_named("circle", seed=1)
    pose = CameraPose(vehicle_id=2, velocity_en_mps=(3.0, 1.0), wind_en_mps=(5.0, 0.0))
    out = []
    for t_s, position, yaw in poses(flood, frames, 10.0, seed=5):
        frame = render_frame(flood, t_s, position, yaw, camera, 1, pose=pose, imaging=spec)
        out.append((frame.image_bgr, height_m(flood, position), camera.fov_deg, yaw))
    return out


def halved(frames: list[Frame]) -> list[Frame]:
    """The same frames at half the side (area-averaged), same field of view."""
    return [(cv2.resize(image, (image.shape[1] // 2, image.shape[0] // 2), interpolation=cv2.INTER_AREA), h, fov, yaw)
            for image, h, fov, yaw in frames]


def _perceive_cpu_s(frame: Frame) -> float:
    """Thread CPU time [s] of one ``perceive`` call on ``frame``."""
    image, h, fov, yaw = frame
    start = time.thread_time()
    perceive(image, h, fov, yaw)
    return time.thread_time() - start


def one_round(cases: dict[str, list[Frame]], sweep: np.ndarray) -> dict[str, float]:
    """p50 thread CPU [ms] of ``perceive`` per case, warm and cold, cases interleaved frame by frame."""
    samples: dict[str, list[float]] = {f"{name}, {state}": [] for name in cases for state in ("warm", "cold")}
    for i in range(len(next(iter(cases.values())))):
        for name, frames in cases.items():
            sweep.sum()
            samples[f"{name}, cold"].append(_perceive_cpu_s(frames[i]))
            samples[f"{name}, warm"].append(_perceive_cpu_s(frames[i]))
    return {key: float(np.median(values)) * 1e3 for key, values in samples.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=300)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--sweep-mib", type=float, default=32.0)
    ns = parser.parse_args()
    cv2.setNumThreads(1)
    clean, turbid = rendered(ImagingSpec(), ns.frames), rendered(MODERATE_TURBID, ns.frames)
    cases = {"clean 128 px": clean, "turbid 128 px": turbid, "clean 64 px": halved(clean),
             "turbid 64 px": halved(turbid)}
    sweep = np.ones(int(ns.sweep_mib * 2**20 / 4), np.float32)
    print(machine())
    rounds = [one_round(cases, sweep) for _ in range(ns.rounds)]
    print("| case | " + " | ".join(f"round {r + 1}" for r in range(ns.rounds)) + " |")
    print("|---|" + "---|" * ns.rounds)
    for key in rounds[0]:
        print(f"| {key} | " + " | ".join(f"{r[key]:.3f}" for r in rounds) + " |")


if __name__ == "__main__":
    main()
