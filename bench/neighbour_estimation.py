"""Benchmark: what the neighbour filter and the relay cost per control step, at 13 and 208 vehicles.

Every drone hears every other (the worst case: ``large`` gives ≈200 heard neighbours per drone), each step each
drone files one fresh state per neighbour (a moving ring), reads its filtered neighbours at the control time and
picks the copies it relays; each state carries the copies its sender picked the step before, which every receiver
unpacks, admits (``relay_admission``: the forged-copy checks) and files. The same step without the filter (the
newest message carried by its age, ``neighbour_info``) is timed beside it, in the same run. CPU time
(``time.process_time``), one process:

    .venv/bin/python bench/neighbour_estimation.py --vehicles 13 208 --steps 40
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

import msgspec  # noqa: E402
import numpy as np  # noqa: E402

from comms.messages import NeighbourState  # noqa: E402
from mission_plan.control_params import ControlParams  # noqa: E402
from vehicle_agents.core.filtered_neighbours import filter_noise, filtered_infos, track_step  # noqa: E402
from vehicle_agents.core.neighbour_filter import EMPTY_BANK  # noqa: E402
from vehicle_agents.core.neighbours import Inbox, heard_after  # noqa: E402
from vehicle_agents.core.relay import relay_copies, unpacked  # noqa: E402
from vehicle_agents.core.relay_admission import admitted  # noqa: E402
from vehicle_agents.onboard_view import neighbour_info  # noqa: E402

DT_S = 0.05


def states_at(n: int, k: int) -> list[NeighbourState]:
    angle = np.arange(n) * 2 * np.pi / n + 0.25 * k * DT_S
    radius = 5.0 + 0.2 * n
    edge = [(float(x), float(x)) for x in range(24)]
    return [NeighbourState(sender_id=i + 1, role="boundary", seq=k + 1, t_s=k * DT_S,
                           position_en_m=(float(radius * np.cos(a)), float(radius * np.sin(a))), altitude_m=10.0,
                           velocity_en_mps=(float(-np.sin(a)), float(np.cos(a))), edge_points_en_m=edge)
            for i, a in enumerate(angle)]


def run(n: int, steps: int) -> dict[str, float]:
    params = ControlParams(mode="improved", neighbour_filter=True, relay_max_hops=3)
    noise = filter_noise(params)
    tables = [{} for _ in range(n)]
    banks = [EMPTY_BANK] * n
    copies: list[list[NeighbourState]] = [[] for _ in range(n)]
    plain_s = filter_s = relay_s = admit_s = file_s = 0.0
    for k in range(steps):
        states = [msgspec.structs.replace(m, relayed=c) for m, c in zip(states_at(n, k), copies)]
        t_s = k * DT_S + 0.1
        for i in range(n):
            c0 = time.process_time()
            inbox_states, _ = admitted(unpacked(states), tables[i], t_s, params.state_rate_hz)
            c1 = time.process_time()
            tables[i], _ = heard_after(tables[i], frozenset(), Inbox(states=inbox_states), i + 1, t_s, 10.0)
            c2 = time.process_time()
            [neighbour_info(m, t_s - m.t_s) for _, m in sorted(tables[i].items())]
            c3 = time.process_time()
            banks[i] = track_step(banks[i], inbox_states, frozenset(), i + 1, noise)
            banks[i], _ = filtered_infos(banks[i], tables[i], t_s, noise)
            c4 = time.process_time()
            copies[i] = relay_copies(tables[i], i + 1, t_s, k + 1, params.relay_max_hops, params.relay_max_age_s,
                                     params.relay_budget_bytes)
            c5 = time.process_time()
            admit_s += c1 - c0
            file_s += c2 - c1
            plain_s += c3 - c2
            filter_s += c4 - c3
            relay_s += c5 - c4
    per_step_ms = 1000.0 / steps
    return {"vehicles": n, "plain_ms_per_step": plain_s * per_step_ms, "filter_ms_per_step": filter_s * per_step_ms,
            "relay_ms_per_step": relay_s * per_step_ms, "admit_ms_per_step": admit_s * per_step_ms,
            "file_ms_per_step": file_s * per_step_ms}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vehicles", type=int, nargs="+", default=[13, 208])
    parser.add_argument("--steps", type=int, default=40)
    args = parser.parse_args()
    for n in args.vehicles:
        r = run(n, args.steps)
        print(f"{r['vehicles']:4d} vehicles: per control step (all drones) plain {r['plain_ms_per_step']:.2f} ms CPU, "
              f"filter {r['filter_ms_per_step']:.2f} ms, relay {r['relay_ms_per_step']:.2f} ms, copies unpacked and "
              f"admitted {r['admit_ms_per_step']:.2f} ms, filed {r['file_ms_per_step']:.2f} ms")


if __name__ == "__main__":
    main()
