"""CPU cost of the onboard odometry correction, of the barrier's sensed neighbours and of the simulated ranging
sensor, per call.

    python -m bench.cooperative_position_cost [--neighbours 12] [--calls 20000]

One GPS-less drone of ``circle``'s 13 hearing ``--neighbours`` others: ``correction_step`` with a new ranging
(what an agent pays at 10 Hz), the same step without one (the other control ticks), the collision barrier's sensed
neighbours (``sensed_offsets`` and ``sensed_positions_en_m``, every control tick of every drone of improved mode under
estimator errors), and ``neighbour_ranging`` for one observer (what the camera process or the lockstep engine pays
per drone at 10 Hz). Median of five repeats.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from comms.messages import NeighbourState
from mission_plan.roles import Role
from mission_plan.weather import SensorSpec
from mock_autopilot.relative_ranging import neighbour_ranging
from vehicle_agents.control.safety import sensed_positions_en_m
from vehicle_agents.control.types import NeighbourInfo
from vehicle_agents.core.cooperative_position import PositionCorrection, correction_step
from vehicle_agents.core.sensed_neighbours import sensed_offsets


def _per_call_us(call, calls: int) -> float:  # noqa: ANN001
    runs = []
    for _ in range(5):
        start = time.perf_counter()
        for k in range(calls):
            call(k)
        runs.append((time.perf_counter() - start) / calls * 1e6)
    return statistics.median(runs)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--neighbours", type=int, default=12)
    parser.add_argument("--calls", type=int, default=20000)
    ns = parser.parse_args()
    rng = np.random.default_rng(1)
    n = ns.neighbours + 1
    positions = rng.uniform(-15.0, 15.0, (n, 2))
    yaws = rng.uniform(-np.pi, np.pi, n)
    ids = list(range(1, n + 1))
    spec = SensorSpec(odometry_drift_frac=0.01)
    ranging = neighbour_ranging(1.0, 0, ids, positions, yaws, spec, seed=1)
    heard = {vid: NeighbourState(sender_id=vid, role=Role.BOUNDARY, seq=1, t_s=0.98,
                                 position_en_m=(float(p[0]), float(p[1])), altitude_m=10.0)
             for vid, p in zip(ids[1:], positions[1:])}
    state = PositionCorrection(flown_m=50.0, last_odometry_en_m=(0.0, 0.0), last_ranging_t_s=0.9)
    odometry, velocity = positions[0] + 0.3, np.zeros(2)
    with_ranging = _per_call_us(lambda k: correction_step(state, odometry, velocity, 0.2, ranging, heard, 1.0,
                                                          0.01, 0.1), ns.calls)
    without = _per_call_us(lambda k: correction_step(state, odometry, velocity, 0.2, None, heard, 1.0, 0.01, 0.1),
                           ns.calls)
    sensor = _per_call_us(lambda k: neighbour_ranging(0.1 * k, 0, ids, positions, yaws, spec, seed=1), ns.calls // 4)
    obstacles = [NeighbourInfo(vid, Role.BOUNDARY, p, np.zeros(2), 10.0, age_s=0.05)
                 for vid, p in zip(ids[1:], positions[1:])]
    barrier_sensing = _per_call_us(
        lambda k: sensed_positions_en_m(obstacles, odometry, velocity, sensed_offsets(ranging, 0.2, 1.05)), ns.calls)
    print(f"{ns.neighbours} neighbours: correction_step with a new ranging {with_ranging:.1f} µs, "
          f"without {without:.1f} µs; the barrier's sensed neighbours {barrier_sensing:.1f} µs per tick; "
          f"neighbour_ranging per observer {sensor:.1f} µs")


if __name__ == "__main__":
    main()
