"""Benchmark: encode/decode time and size of every comms message kind.

Run: .venv/bin/python bench/comms_codec.py [--repeat 20000]
Prints a Markdown table (µs per operation, best of 5 runs, and bytes on the wire).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from comms.frames import GeodeticHome  # noqa: E402
from comms.messages import (  # noqa: E402
    CameraFrame,
    GroundTruth,
    MissionCommand,
    NeighbourState,
    RadioBundle,
    decode,
    encode,
    flood_polygon_from_enu,
)
from mission_plan.roles import Role  # noqa: E402


def _samples() -> list[tuple[str, object]]:
    rng = np.random.default_rng(0)
    minimal = NeighbourState(sender_id=3, role=Role.FOLLOWER, seq=1234, t_s=12.5, position_en_m=(3.2, -7.9), altitude_m=10.0,
                             velocity_en_mps=(0.4, 0.1))
    boundary = NeighbourState(sender_id=3, role=Role.BOUNDARY, seq=1234, t_s=12.5, position_en_m=(13.2, -2.9), altitude_m=10.0,
                              velocity_en_mps=(0.4, 0.9), lat_deg=47.39, lon_deg=8.54, flags=0b1111, battery_fraction=0.9,
                              group="A", edge_points_en_m=[tuple(p) for p in rng.uniform(-20, 20, (32, 2)).tolist()])
    truth = GroundTruth(t_s=1.0, vehicle_ids=list(range(300)), positions_enu_m=[tuple(p) for p in rng.uniform(-50, 50, (300, 3)).tolist()],
                        velocities_enu_mps=[tuple(p) for p in rng.uniform(-1, 1, (300, 3)).tolist()], yaw_ned_rad=rng.uniform(-3, 3, 300).tolist(),
                        alive=[True] * 300)
    import cv2

    image = rng.integers(0, 255, (128, 128, 3), dtype=np.uint8)
    image = cv2.GaussianBlur(image, (9, 9), 3)
    png = cv2.imencode(".png", image)[1].tobytes()
    camera = CameraFrame(vehicle_id=3, seq=1, t_s=1.0, altitude_m=10.0, yaw_ned_rad=0.2, fov_deg=60.0, width_px=128, height_px=128,
                         encoding="png", image=png)
    camera_raw = CameraFrame(vehicle_id=3, seq=1, t_s=1.0, altitude_m=10.0, yaw_ned_rad=0.2, fov_deg=60.0, width_px=128, height_px=128,
                             encoding="raw_bgr", image=image.tobytes())
    bundle = RadioBundle(t_s=1.0, entries=[(i, encode(minimal)) for i in range(20)])
    angles = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    polygon = flood_polygon_from_enu(np.c_[14 * np.cos(angles), 14 * np.sin(angles)], GeodeticHome(), mission="circle", t_s=30.0)
    command = MissionCommand(seq=1, t_s=1.0, command="start", phase="caging", flood_clock_start_t_s=1.0)
    return [
        ("NeighbourState (minimal)", minimal),
        ("NeighbourState (boundary, 32 edge points)", boundary),
        ("RadioBundle (20 states)", bundle),
        ("GroundTruth (300 vehicles)", truth),
        ("CameraFrame (128x128 PNG)", camera),
        ("CameraFrame (128x128 raw BGR)", camera_raw),
        ("FloodPolygon (GeoJSON, 64 vertices)", polygon),
        ("MissionCommand", command),
    ]


def _best_us(fn: Callable[[], object], repeat: int) -> float:
    best = float("inf")
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(repeat):
            fn()
        best = min(best, (time.perf_counter() - t0) / repeat)
    return best * 1e6


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=20000)
    args = parser.parse_args(argv)
    print("| message | bytes | encode µs | decode µs |")
    print("|---|---:|---:|---:|")
    for name, msg in _samples():
        payload = encode(msg)  # type: ignore[arg-type]
        kind = type(msg)
        assert decode(kind, payload) == msg
        n = max(200, args.repeat // max(1, len(payload) // 2000))
        enc = _best_us(lambda: encode(msg), n)  # type: ignore[arg-type]
        dec = _best_us(lambda: decode(kind, payload), n)
        print(f"| {name} | {len(payload)} | {enc:.2f} | {dec:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
