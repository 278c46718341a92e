"""The mock PX4's velocity loop reads the plant's response time from VehicleConfig, as the lockstep kinematics do."""

import numpy as np
import pytest

from mock_autopilot.backends.interface import VehicleRequest
from mock_autopilot.backends.px4 import Px4Backend, px4_vehicle_configs
from mock_autopilot.kinematics import KinematicLimits, KinematicState, step_kinematics
from mock_autopilot.vehicle import PHYSICS_STEP_S

DT_S = 0.05
STEP_NED_MPS = np.array([0.5, 0.0, 0.0])  # small enough that MPC_ACC_HOR never clamps: a pure first-order response


def velocity_after_step(response_time_s: float, seconds: float) -> tuple[np.ndarray, np.ndarray]:
    """(Vehicle's velocity, step_kinematics' velocity) ``seconds`` after a velocity step in OFFBOARD."""
    limits = KinematicLimits(response_time_s=response_time_s)
    backend = Px4Backend(px4_vehicle_configs(limits, 5.0, [(0.0, 0.0, 0.0)]))
    start = backend.hover_start(5.0)
    assert backend.vehicles[0].config.response_time_s == response_time_s
    expected = KinematicState(start.position_ned_m[0].copy(), start.velocity_ned_mps[0].copy())
    for _ in range(int(round(seconds / DT_S))):
        state = backend.step(STEP_NED_MPS[None, :], np.zeros(1), np.ones(1, bool), [VehicleRequest.NONE], DT_S)
        remaining = DT_S
        while remaining > 1e-9:  # the vehicle's own 50 Hz physics steps within one control period
            dt = min(PHYSICS_STEP_S, remaining)
            expected = step_kinematics(expected, STEP_NED_MPS, limits, dt)
            remaining -= dt
    return state.velocity_ned_mps[0], expected.velocity_ned_mps


def test_slower_response_time_responds_slower_and_matches_step_kinematics() -> None:
    fast, fast_expected = velocity_after_step(0.3, 0.3)
    slow, slow_expected = velocity_after_step(0.6, 0.3)
    assert fast[0] == pytest.approx(0.5 * (1 - np.exp(-1.0)), abs=2e-3)
    assert slow[0] == pytest.approx(0.5 * (1 - np.exp(-0.5)), abs=2e-3)
    assert slow[0] < fast[0] - 0.1
    np.testing.assert_allclose(fast, fast_expected, atol=1e-9)
    np.testing.assert_allclose(slow, slow_expected, atol=1e-9)
