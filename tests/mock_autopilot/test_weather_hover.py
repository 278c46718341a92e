"""A multicopter hovering in wind: PX4's velocity loop holds it near its setpoint (truth), gusts and eddies move it.

The specified figure: 120 s in a 6 m/s mean wind with moderate Dryden turbulence, horizontal error from the
setpoint p95 <= 1.5 m and max <= 3 m, on both vehicle backends.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mission_plan.dynamics import KinematicLimits
from mission_plan.weather import SensorSpec, WindSpec
from mock_autopilot.backends.interface import VehicleRequest
from mock_autopilot.backends.kinematic import KinematicBackend
from mock_autopilot.backends.px4 import Px4Backend, px4_vehicle_configs
from mock_autopilot.weather_model import Weather

WINDY = WindSpec(speed_mps=6.0, from_deg=270.0, turbulence="moderate")
HOVER_S = 120.0
DT_S = 0.05


def _errors(positions_ned_m: list[np.ndarray], target_ned_m: np.ndarray) -> np.ndarray:
    return np.array([math.hypot(p[0] - target_ned_m[0], p[1] - target_ned_m[1]) for p in positions_ned_m])


@pytest.mark.parametrize("seed", [1, pytest.param(2, marks=pytest.mark.slow)])
def test_px4_hold_in_wind_stays_within_the_specified_bounds(seed: int) -> None:
    configs = px4_vehicle_configs(KinematicLimits(), 10.0, [(0.0, 0.0)], weather=Weather(WINDY, seed=seed))
    backend = Px4Backend(configs)
    backend.hover_start(10.0)
    state = backend.step(np.zeros((1, 3)), np.zeros(1), np.array([True]), [VehicleRequest.HOLD], DT_S)
    target = backend.vehicles[0].hold_ned.copy()
    truth = []
    for _ in range(int(HOVER_S / DT_S)):
        state = backend.step(np.zeros((1, 3)), np.zeros(1), np.array([False]), [VehicleRequest.NONE], DT_S)
        truth.append(state.position_ned_m[0].copy())
    assert state.flight_mode[0] == "AUTO.LOITER"
    errors = _errors(truth, target)
    assert np.percentile(errors, 95) <= 1.5
    assert errors.max() <= 3.0
    assert errors.max() > 0.1  # the wind does move it
    roll = state.tilt_rad[0][0]
    assert roll < 0.0  # a west wind pushes east: the drone leans into it (left)


def _kinematic_hover(weather: Weather) -> tuple[np.ndarray, np.ndarray, object]:
    """Truth errors from the start point of a kinematic vehicle whose position loop (PX4's MPC_XY_P) holds its
    estimate there, and the last state."""
    backend = KinematicBackend(KinematicLimits(), 1, weather, [1], [True])
    state = backend.hover_start(10.0)
    target = state.position_ned_m[0].copy()
    truth = []
    for _ in range(int(HOVER_S / DT_S)):
        command = 0.95 * (target - state.reported_position_ned_m[0])
        state = backend.step(command[None, :], np.zeros(1), np.array([True]), [VehicleRequest.NONE], DT_S)
        truth.append(state.position_ned_m[0].copy())
    return _errors(truth, target), target, state


def test_kinematic_backend_under_a_position_loop_stays_within_the_specified_bounds() -> None:
    errors, _, _ = _kinematic_hover(Weather(WINDY, seed=3))
    assert np.percentile(errors, 95) <= 1.5
    assert errors.max() <= 3.0


def test_hovering_drone_wanders_with_its_gps() -> None:
    """Still air, noisy GPS: the autopilot holds its estimate, so the truth wanders by about the GPS error."""
    sensors = SensorSpec(gps_white_sigma_m=0.3, gps_bias_sigma_m=0.5, gps_bias_tau_s=60.0)
    errors, _, state = _kinematic_hover(Weather(WindSpec(), sensors, seed=4))
    assert 0.1 < float(np.median(errors)) < 2.0
    assert not np.allclose(state.reported_position_ned_m, state.position_ned_m)
