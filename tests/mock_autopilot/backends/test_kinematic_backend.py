"""The kinematic backend: today's lockstep dynamics (``step_kinematics``) over arrays, and what it leaves out."""

import numpy as np
import pytest

from mock_autopilot.backends.interface import VehicleRequest
from mock_autopilot.backends.kinematic import LAND_SPEED_MPS, KinematicBackend, step_kinematics_batch
from mock_autopilot.kinematics import KinematicLimits, KinematicState, step_kinematics

DT_S = 0.05
LIMITS = [
    KinematicLimits(),
    KinematicLimits(response_time_s=0.6),
    KinematicLimits(max_xy_speed_mps=2.0, max_climb_speed_mps=1.0, max_descent_speed_mps=0.5,
                    max_xy_accel_mps2=1.0, max_z_accel_mps2=0.5, response_time_s=0.05),
]


def none(n: int) -> list[VehicleRequest]:
    return [VehicleRequest.NONE] * n


@pytest.mark.parametrize("limits", LIMITS)
def test_batch_step_matches_step_kinematics_per_vehicle(limits: KinematicLimits) -> None:
    rng = np.random.default_rng(7)
    n = 40
    position = np.column_stack((rng.uniform(-5, 5, n), rng.uniform(-5, 5, n), rng.uniform(-3, 0, n)))
    velocity = rng.normal(0.0, 2.0, (n, 3))
    states = [KinematicState(position[i].copy(), velocity[i].copy()) for i in range(n)]
    for k in range(200):
        setpoint = rng.normal(0.0, 6.0, (n, 3))  # beyond every clamp, and often down into the ground
        setpoint[k % n] = 0.0
        position, velocity = step_kinematics_batch(position, velocity, setpoint, limits, DT_S)
        states = [step_kinematics(s, setpoint[i], limits, DT_S) for i, s in enumerate(states)]
        expected_p = np.array([s.position_ned_m for s in states])
        expected_v = np.array([s.velocity_ned_mps for s in states])
        np.testing.assert_allclose(position, expected_p, rtol=0.0, atol=1e-9)
        np.testing.assert_allclose(velocity, expected_v, rtol=0.0, atol=1e-9)
    assert (position[:, 2] <= 0.0).all()


def test_backend_flies_step_kinematics_from_the_hover() -> None:
    limits = KinematicLimits(response_time_s=0.45)
    n = 5
    backend = KinematicBackend(limits, n)
    start = backend.hover_start(8.0)
    assert start.t_s == 0.0 and start.flight_mode == ("OFFBOARD",) * n
    assert start.armed.all() and start.in_air.all() and start.alive.all()
    np.testing.assert_array_equal(start.position_ned_m, np.tile([0.0, 0.0, -8.0], (n, 1)))
    states = [KinematicState(np.array([0.0, 0.0, -8.0]), np.zeros(3)) for _ in range(n)]
    flying = np.zeros((n, 3))
    rng = np.random.default_rng(3)
    for k in range(100):
        setpoint = rng.normal(0.0, 3.0, (n, 3))
        sent = rng.random(n) < 0.7  # unsent: PX4 keeps the previous setpoint
        flying[sent] = setpoint[sent]
        state = backend.step(setpoint, np.zeros(n), sent, none(n), DT_S)
        states = [step_kinematics(s, flying[i], limits, DT_S) for i, s in enumerate(states)]
        np.testing.assert_allclose(state.position_ned_m, [s.position_ned_m for s in states], rtol=0.0, atol=1e-9)
        np.testing.assert_allclose(state.velocity_ned_mps, [s.velocity_ned_mps for s in states], rtol=0.0, atol=1e-9)
    assert state.t_s == pytest.approx(100 * DT_S)


def test_no_offboard_loss_without_setpoints_documented_difference_to_px4() -> None:
    backend = KinematicBackend(KinematicLimits(), 2)
    backend.hover_start(5.0)
    backend.step(np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]), np.zeros(2), np.ones(2, bool), none(2), DT_S)
    for _ in range(60):  # 3 s without a setpoint: far beyond COM_OF_LOSS_T
        state = backend.step(np.zeros((2, 3)), np.zeros(2), np.zeros(2, bool), none(2), DT_S)
    assert state.flight_mode == ("OFFBOARD", "OFFBOARD")
    np.testing.assert_allclose(state.velocity_ned_mps, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], atol=1e-3)


def test_land_descends_and_disarms_hold_stops_other_requests_ignored() -> None:
    backend = KinematicBackend(KinematicLimits(), 3)
    backend.hover_start(2.0)
    moving = np.tile([1.0, 0.0, 0.0], (3, 1))
    backend.step(moving, np.zeros(3), np.ones(3, bool), none(3), DT_S)
    requests = [VehicleRequest.LAND, VehicleRequest.HOLD, VehicleRequest.ARM]
    state = backend.step(moving, np.zeros(3), np.ones(3, bool), requests, DT_S)
    assert state.flight_mode == ("AUTO.LAND", "AUTO.LOITER", "OFFBOARD")
    for _ in range(40):
        state = backend.step(moving, np.zeros(3), np.ones(3, bool), none(3), DT_S)
    assert state.in_air[0] and state.velocity_ned_mps[0, 2] == pytest.approx(LAND_SPEED_MPS, abs=2e-3)
    np.testing.assert_allclose(state.velocity_ned_mps[1], 0.0, atol=1e-3)  # setpoints are not flown in Hold
    assert state.velocity_ned_mps[2, 0] == pytest.approx(1.0, abs=1e-3)
    for _ in range(100):
        state = backend.step(moving, np.zeros(3), np.ones(3, bool), none(3), DT_S)
    assert not state.armed[0] and not state.in_air[0] and state.position_ned_m[0, 2] == 0.0
    assert state.flight_mode[0] == "AUTO.LOITER"  # PX4's mode after an automatic landing
    assert state.armed[1:].all() and state.in_air[1:].all()


def test_yaw_follows_the_setpoint_and_nan_keeps_it() -> None:
    backend = KinematicBackend(KinematicLimits(), 2)
    backend.hover_start(5.0)
    state = backend.step(np.zeros((2, 3)), np.array([1.0, -1.0]), np.ones(2, bool), none(2), DT_S)
    np.testing.assert_allclose(state.yaw_ned_rad, [1.0, 2 * np.pi - 1.0])
    state = backend.step(np.zeros((2, 3)), np.array([np.nan, 0.5]), np.ones(2, bool), none(2), DT_S)
    np.testing.assert_allclose(state.yaw_ned_rad, [1.0, 0.5])


def test_nan_setpoint_is_refused_and_the_previous_one_flown() -> None:
    backend = KinematicBackend(KinematicLimits(), 1)
    backend.hover_start(5.0)
    backend.step(np.array([[1.0, 0.0, 0.0]]), np.zeros(1), np.ones(1, bool), none(1), DT_S)
    for _ in range(60):
        state = backend.step(np.array([[np.nan, 0.0, 0.0]]), np.zeros(1), np.ones(1, bool), none(1), DT_S)
    assert np.isfinite(state.position_ned_m).all()
    assert state.velocity_ned_mps[0, 0] == pytest.approx(1.0, abs=1e-3)


def test_killed_vehicle_falls_to_the_ground_and_stays_dead() -> None:
    backend = KinematicBackend(KinematicLimits(), 2)
    backend.hover_start(5.0)
    backend.kill(1)
    requests = [VehicleRequest.NONE, VehicleRequest.LAND]
    for _ in range(60):
        state = backend.step(np.zeros((2, 3)), np.zeros(2), np.ones(2, bool), requests, DT_S)
    assert list(state.alive) == [True, False] and list(state.armed) == [True, False]
    assert state.position_ned_m[1, 2] == 0.0 and not state.in_air[1]
    assert state.position_ned_m[0, 2] == pytest.approx(-5.0)
