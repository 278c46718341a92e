"""CPU cost of weather on both vehicle backends: the same hover with still air / exact sensors and with `moderate`.

    python -m bench.weather_cost [--sim 60]

Prints CPU seconds per simulated second for the mock PX4 (one vehicle, 50 Hz physics, stepped at 20 Hz as the
lockstep px4 backend does) and for the kinematic backend (13 vehicles, 20 Hz), calm and moderate, taken in one run.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from mission_plan.dynamics import KinematicLimits
from mission_plan.scenario_files import load_scenario
from mock_autopilot.backends.interface import VehicleRequest
from mock_autopilot.backends.kinematic import KinematicBackend
from mock_autopilot.backends.px4 import Px4Backend, px4_vehicle_configs
from mock_autopilot.weather_model import Weather

DT_S = 0.05


def _cpu_per_sim_s(backend: object, n: int, sim_s: float) -> float:
    backend.hover_start(10.0)  # type: ignore[attr-defined]
    zeros, yaws, sent = np.zeros((n, 3)), np.zeros(n), np.ones(n, dtype=bool)
    requests = [VehicleRequest.NONE] * n
    start = time.process_time()
    for _ in range(int(sim_s / DT_S)):
        backend.step(zeros, yaws, sent, requests, DT_S)  # type: ignore[attr-defined]
    return (time.process_time() - start) / sim_s


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sim", type=float, default=60.0, help="simulated seconds per case")
    ns = parser.parse_args()
    for name in ("calm", "moderate"):
        scenario = load_scenario("circle", [f"weather={name}"])
        weather = Weather(scenario.wind, scenario.sensors, scenario.seed, scenario.altitude_m)
        px4 = Px4Backend(px4_vehicle_configs(KinematicLimits(), 10.0, [(0.0, 0.0)], weather=weather))
        n = len(scenario.vehicles)
        kinematic = KinematicBackend(KinematicLimits(), n, weather, [v.vehicle_id for v in scenario.vehicles],
                                     [v.has_gps for v in scenario.vehicles])
        print(f"{name:9s} px4 (1 vehicle): {_cpu_per_sim_s(px4, 1, ns.sim) * 1e3:6.2f} ms CPU per simulated s; "
              f"kinematic ({n} vehicles): {_cpu_per_sim_s(kinematic, n, ns.sim) * 1e3:6.2f} ms")


if __name__ == "__main__":
    main()
