"""Benchmark: cost of one vehicle-step (one vehicle, one 20 Hz control period) of each vehicle backend.

Both backends fly the same fleet through the same setpoints after ``hover_start``: every vehicle streams a velocity
setpoint that turns slowly (as the boundary law's tangential command does), so the mock PX4's offboard path,
timers and 50 Hz physics all run. Prints microseconds (CPU) per vehicle-step of each backend and
their ratio, today's per-vehicle ``step_kinematics`` loop for reference, and the px4 backend's one-off
``hover_start`` (the real arm / take-off / OFFBOARD sequence).

    .venv/bin/python -m bench.vehicle_backends [--vehicles 13 208] [--sim 10] [--rate 20]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from mock_autopilot.backends.interface import VehicleBackend, VehicleRequest
from mock_autopilot.backends.kinematic import KinematicBackend
from mock_autopilot.backends.px4 import Px4Backend, px4_vehicle_configs
from mock_autopilot.kinematics import KinematicLimits, KinematicState, step_kinematics

ALTITUDE_M = 10.0


def setpoint_schedule(n: int, sim_s: float, rate_hz: float) -> list[np.ndarray]:
    """(N,3) velocity setpoints [m/s NED] for every period: 2 m/s, each vehicle's heading turning at 0.2 rad/s."""
    phase = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    schedule = []
    for k in range(int(round(sim_s * rate_hz))):
        heading = phase + 0.2 * k / rate_hz
        schedule.append(np.column_stack((2.0 * np.cos(heading), 2.0 * np.sin(heading), np.zeros(n))))
    return schedule


def run(backend: VehicleBackend, schedule: list[np.ndarray], rate_hz: float) -> float:
    """CPU seconds [s] of stepping ``backend`` through ``schedule`` (after its hover_start)."""
    n = backend.vehicle_count
    sent = np.ones(n, dtype=bool)
    requests = [VehicleRequest.NONE] * n
    yaws = np.zeros(n)
    dt_s = 1.0 / rate_hz
    start = time.process_time()
    for setpoints in schedule:
        backend.step(setpoints, yaws, sent, requests, dt_s)
    return time.process_time() - start


def run_step_kinematics(limits: KinematicLimits, schedule: list[np.ndarray], rate_hz: float) -> float:
    """CPU seconds [s] of the lockstep engine's loop before the backends: ``step_kinematics`` once per vehicle."""
    n = len(schedule[0])
    states = [KinematicState(np.array([0.0, 0.0, -ALTITUDE_M]), np.zeros(3)) for _ in range(n)]
    dt_s = 1.0 / rate_hz
    start = time.process_time()
    for setpoints in schedule:
        states = [step_kinematics(s, setpoints[i], limits, dt_s) for i, s in enumerate(states)]
    return time.process_time() - start


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--vehicles", type=int, nargs="*", default=[13, 208])
    parser.add_argument("--sim", type=float, default=10.0, help="simulated seconds after hover_start")
    parser.add_argument("--rate", type=float, default=20.0, help="control rate [Hz]")
    ns = parser.parse_args()
    limits = KinematicLimits()
    print("| vehicles | kinematic backend [µs/vehicle-step] | px4 backend [µs/vehicle-step] | px4 / kinematic "
          "| step_kinematics per vehicle, before [µs/vehicle-step] | px4 hover_start CPU [s] |")
    print("|---|---|---|---|---|---|")
    for n in ns.vehicles:
        schedule = setpoint_schedule(n, ns.sim, ns.rate)
        vehicle_steps = n * len(schedule)
        kinematic = KinematicBackend(limits, n)
        kinematic.hover_start(ALTITUDE_M)
        kinematic_us = run(kinematic, schedule, ns.rate) / vehicle_steps * 1e6
        loop_us = run_step_kinematics(limits, schedule, ns.rate) / vehicle_steps * 1e6
        pads = [(2.0 * (i % 20), 2.0 * (i // 20), 0.0) for i in range(n)]
        px4 = Px4Backend(px4_vehicle_configs(limits, ALTITUDE_M, pads))
        hover_start = time.process_time()
        px4.hover_start(ALTITUDE_M)
        hover_s = time.process_time() - hover_start
        px4_us = run(px4, schedule, ns.rate) / vehicle_steps * 1e6
        print(f"| {n} | {kinematic_us:.2f} | {px4_us:.1f} | {px4_us / kinematic_us:.0f} | {loop_us:.2f} "
              f"| {hover_s:.2f} |", flush=True)


if __name__ == "__main__":
    main()
