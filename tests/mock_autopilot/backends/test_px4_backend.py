"""The px4 backend: the sans-IO mock PX4 driven through MAVLink, against the kinematic backend where they agree."""

import math

import numpy as np
import pytest
from pymavlink.dialects.v20 import common as mavlink

from mock_autopilot.backends.interface import BackendState, VehicleRequest
from mock_autopilot.backends.kinematic import KinematicBackend
from mock_autopilot.backends.px4 import Px4Backend, px4_vehicle_configs
from mock_autopilot.kinematics import KinematicLimits

DT_S = 0.05
ACCEPTED, TEMPORARILY_REJECTED = 0, 1
NONE = VehicleRequest.NONE


def px4(n: int = 1, altitude_m: float = 10.0, limits: KinematicLimits = KinematicLimits(), **params: float
        ) -> Px4Backend:
    """N mock PX4s on pads 3.6 m apart, every other one without GPS."""
    pads = [(3.0 * i, -2.0 * i, 0.0) for i in range(n)]
    gps = [i % 2 == 0 for i in range(n)]
    return Px4Backend(px4_vehicle_configs(limits, altitude_m, pads, has_gps=gps, params=params))


def fly(backend: Px4Backend | KinematicBackend, seconds: float,
        velocity_ned_mps: tuple[float, float, float] = (0.0, 0.0, 0.0), sent: bool = True,
        requests: tuple[VehicleRequest, ...] = ()) -> BackendState:
    """Step every vehicle with one setpoint for ``seconds``; ``requests`` go with the first period."""
    n = backend.vehicle_count
    setpoints = np.tile(velocity_ned_mps, (n, 1))
    first = list(requests) or [NONE] * n
    state = backend.state()
    for k in range(int(round(seconds / DT_S))):
        state = backend.step(setpoints, np.zeros(n), np.full(n, sent), first if k == 0 else [NONE] * n, DT_S)
    return state


def test_hover_start_flies_arm_takeoff_hold_offboard_to_the_altitude() -> None:
    backend = px4(3, altitude_m=10.0)
    state = backend.hover_start(10.0)
    assert state.t_s == 0.0
    assert state.armed.all() and state.in_air.all() and state.alive.all()
    assert state.flight_mode == ("OFFBOARD",) * 3
    np.testing.assert_allclose(state.position_ned_m[:, 2], -10.0, atol=0.3)
    np.testing.assert_allclose(state.position_ned_m[:, :2], 0.0, atol=0.01)
    assert np.abs(state.velocity_ned_mps).max() < 0.002
    assert backend.vehicle_time_s > 10.0 / 1.5  # the real climb at MPC_TKO_SPEED happened on the vehicles' clock
    for i in range(3):
        acks = backend.acks(i)
        assert acks[(mavlink.MAV_CMD_COMPONENT_ARM_DISARM, ACCEPTED)] == 1
        assert acks[(mavlink.MAV_CMD_NAV_TAKEOFF, ACCEPTED)] == 1
        assert acks[(mavlink.MAV_CMD_DO_SET_MODE, ACCEPTED)] == 1
        assert not backend.rejections(i)
    assert fly(backend, 1.0).t_s == pytest.approx(1.0)


@pytest.mark.parametrize("limits", [
    KinematicLimits(),
    KinematicLimits(response_time_s=0.6),
    KinematicLimits(max_xy_speed_mps=3.0, max_xy_accel_mps2=2.0, max_climb_speed_mps=1.0, max_z_accel_mps2=2.0),
], ids=["default", "slow_response", "tight_limits"])
def test_velocity_step_gives_the_kinematic_trajectory(limits: KinematicLimits) -> None:
    """Both backends fly the same first-order response and clamps; the mock PX4 integrates it at 50 Hz inside each
    20 Hz period (20, 20, 10 ms) where the kinematic backend takes one 50 ms step. The first-order velocity response
    composes exactly across sub-steps (e^-a e^-b = e^-(a+b)), so what differs is: the acceleration clamp, applied per
    sub-step when it engages or releases inside a period (< 1 mm/s here); trapezoidal position integration at two
    step sizes, O(dt^2 / tau) over the transient (~0.5 mm); and the px4 hover's residual at mission time 0 (< 1 mm/s,
    ~1 mm). Hence 1 cm and 1 cm/s with margin, over a 3 s step and a 2 s stop, climbing too."""
    p, k = px4(2, limits=limits), KinematicBackend(limits, 2)
    p0, k0 = p.hover_start(10.0), k.hover_start(10.0)
    sent, yaws = np.ones(2, bool), np.zeros(2)
    for j in range(100):
        setpoint = np.tile([4.0, -2.0, -1.0] if j < 60 else [0.0, 0.0, 0.0], (2, 1))
        ps = p.step(setpoint, yaws, sent, [NONE] * 2, DT_S)
        ks = k.step(setpoint, yaws, sent, [NONE] * 2, DT_S)
        assert ps.t_s == pytest.approx(ks.t_s)
        displacement_m = ks.position_ned_m - k0.position_ned_m
        np.testing.assert_allclose(ps.position_ned_m - p0.position_ned_m, displacement_m, atol=0.01)
        np.testing.assert_allclose(ps.velocity_ned_mps, ks.velocity_ned_mps, atol=0.01)
    assert ps.position_ned_m[0, 0] - p0.position_ned_m[0, 0] > 5.0  # it did fly


@pytest.mark.parametrize(("com_obl_rc_act", "mode"), [(0, "POSCTL"), (5, "AUTO.LOITER"), (4, "AUTO.LAND")])
def test_offboard_loss_failsafe_in_px4_not_in_the_kinematic_backend(com_obl_rc_act: int, mode: str) -> None:
    backend = px4(2, COM_OBL_RC_ACT=com_obl_rc_act)
    backend.hover_start(5.0)
    kinematic = KinematicBackend(KinematicLimits(), 2)
    kinematic.hover_start(5.0)
    assert fly(backend, 0.9, sent=False).flight_mode == ("OFFBOARD",) * 2  # within COM_OF_LOSS_T = 1 s
    assert fly(backend, 0.2, sent=False).flight_mode == (mode,) * 2
    assert fly(kinematic, 1.1, sent=False).flight_mode == ("OFFBOARD",) * 2  # documented: not modelled


def test_refused_command_is_counted_and_offboard_can_be_resumed() -> None:
    backend = px4(1)
    backend.hover_start(5.0)
    fly(backend, 1.5, sent=False)  # offboard lost -> POSCTL
    assert any("offboard lost" in text for text in backend.texts(0))
    state = fly(backend, DT_S, sent=False, requests=(VehicleRequest.START_OFFBOARD,))
    assert state.flight_mode == ("POSCTL",)
    assert backend.acks(0)[(mavlink.MAV_CMD_DO_SET_MODE, TEMPORARILY_REJECTED)] == 1  # PX4: no setpoint stream
    state = fly(backend, DT_S, sent=True, requests=(VehicleRequest.START_OFFBOARD,))  # setpoint first, as MAVSDK
    assert state.flight_mode == ("OFFBOARD",)
    assert fly(backend, DT_S, requests=(VehicleRequest.HOLD,)).flight_mode == ("AUTO.LOITER",)


def test_land_request_lands_and_disarms() -> None:
    backend = px4(2)
    backend.hover_start(3.0)
    state = fly(backend, DT_S, requests=(VehicleRequest.LAND, NONE))
    assert state.flight_mode == ("AUTO.LAND", "OFFBOARD")
    for _ in range(300):  # 3 m at MPC_LAND_SPEED, the land detector, COM_DISARM_LAND: about 7 s
        state = backend.step(np.zeros((2, 3)), np.zeros(2), np.array([False, True]), [NONE] * 2, DT_S)
        if not state.armed[0]:
            break
    assert not state.armed[0] and not state.in_air[0] and state.position_ned_m[0, 2] == pytest.approx(0.0, abs=0.05)
    assert state.flight_mode == ("AUTO.LOITER", "OFFBOARD")  # PX4 returns to Hold after an automatic landing
    assert state.armed[1] and state.in_air[1]
    assert backend.acks(0)[(mavlink.MAV_CMD_NAV_LAND, ACCEPTED)] == 1


def test_gcs_heartbeats_keep_the_datalink_failsafe_quiet() -> None:
    backend = px4(1, NAV_DLL_ACT=3, COM_DL_LOSS_T=5)
    backend.hover_start(5.0)
    assert fly(backend, 8.0, (0.5, 0.0, 0.0)).flight_mode == ("OFFBOARD",)
    params = {"NAV_DLL_ACT": 3, "COM_DL_LOSS_T": 5}
    configs = px4_vehicle_configs(KinematicLimits(), 5.0, [(0.0, 0.0, 0.0)], params=params)
    silent = Px4Backend(configs, gcs_heartbeat_period_s=math.inf)
    with pytest.raises(RuntimeError, match="GCS connection lost"):  # one heartbeat at boot, none in the climb: lands
        silent.hover_start(5.0)


def test_killed_vehicle_falls_and_ignores_requests() -> None:
    backend = px4(2)
    backend.hover_start(5.0)
    backend.kill(0)
    state = fly(backend, 3.0, requests=(VehicleRequest.LAND, NONE))
    assert list(state.alive) == [False, True] and not state.armed[0] and not state.in_air[0]
    assert state.position_ned_m[0, 2] == 0.0
    assert not backend.acks(0)[(mavlink.MAV_CMD_NAV_LAND, ACCEPTED)]
    assert state.flight_mode[1] == "OFFBOARD" and state.position_ned_m[1, 2] == pytest.approx(-5.0, abs=0.3)
