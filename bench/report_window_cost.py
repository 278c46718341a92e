"""CPU cost of the ground station's caged polygon from the newest reports alone and from the last half second's.

    python -m bench.report_window_cost [--drones 8] [--points 24] [--rate-hz 20] [--calls 200]

``--drones`` boundary drones round a 16 m circle, each reporting ``--points`` noisy edge points of its arc at
``--rate-hz``: ``aggregate_polygon`` over the newest messages, the same over the history of
:data:`gcs.polygon.report_window.WINDOW_S` (what both engines build once per ``polygon_period_s``), and
``remembered`` (what they pay at every step or poll). Median of five repeats, per call.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from collections.abc import Callable

import numpy as np

from comms.messages import NeighbourState
from gcs.polygon.report_window import WINDOW_S, remembered
from gcs.polygon.reports import aggregate_polygon


def _per_call_us(call: Callable[[], object], calls: int) -> float:
    runs = []
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(calls):
            call()
        runs.append((time.perf_counter() - start) / calls * 1e6)
    return statistics.median(runs)


def _message(vehicle_id: int, drones: int, points: int, t_s: float, rng: np.random.Generator) -> NeighbourState:
    angle = 2.0 * math.pi * (vehicle_id - 1) / drones
    arc = np.linspace(angle - math.pi / drones, angle + math.pi / drones, points)
    radius = 16.0 + rng.normal(0.0, 0.05, points)
    edge = np.column_stack([radius * np.cos(arc), radius * np.sin(arc)])
    return NeighbourState(sender_id=vehicle_id, role="boundary", seq=1, t_s=t_s,
                          position_en_m=(16.0 * math.cos(angle), 16.0 * math.sin(angle)), altitude_m=10.0,
                          edge_points_en_m=[tuple(p) for p in edge])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--drones", type=int, default=8)
    parser.add_argument("--points", type=int, default=24)
    parser.add_argument("--rate-hz", type=float, default=20.0)
    parser.add_argument("--calls", type=int, default=200)
    ns = parser.parse_args()
    rng = np.random.default_rng(1)
    order = list(range(1, ns.drones + 1))
    history: dict = {}
    steps = int(round(WINDOW_S * ns.rate_hz)) + 1
    heard: dict[int, NeighbourState] = {}
    for k in range(steps):
        t_s = 10.0 + k / ns.rate_hz
        heard = {vid: _message(vid, ns.drones, ns.points, t_s, rng) for vid in order}
        history = remembered(history, heard, order, t_s)
    now_s = 10.0 + (steps - 1) / ns.rate_hz
    newest = _per_call_us(lambda: aggregate_polygon(heard, order, np.zeros(2), now_s, 1.0), ns.calls)
    fused = _per_call_us(lambda: aggregate_polygon(heard, order, np.zeros(2), now_s, 1.0, history), ns.calls)
    keep = _per_call_us(lambda: remembered(history, heard, order, now_s), ns.calls * 10)
    reports = sum(len(v) for v in history.values())
    print(f"{ns.drones} drones x {ns.points} points at {ns.rate_hz:g} Hz ({reports} reports in {WINDOW_S} s): "
          f"polygon from the newest {newest / 1e3:.2f} ms, from the window {fused / 1e3:.2f} ms "
          f"({fused / newest:.2f}x); remembered {keep:.1f} µs per step")


if __name__ == "__main__":
    main()
