"""What the lockstep engine may rely on from any vehicle backend (the VehicleBackend contract), for both."""

from typing import Callable

import numpy as np
import pytest

from comms.px4 import Px4Mode
from mock_autopilot.backends.interface import MAVSDK_MODE_NAMES, BackendState, VehicleBackend, VehicleRequest
from mock_autopilot.backends.kinematic import KinematicBackend
from mock_autopilot.backends.px4 import Px4Backend, px4_vehicle_configs
from mock_autopilot.kinematics import KinematicLimits

N = 3
DT_S = 0.05
BACKENDS: dict[str, Callable[[], VehicleBackend]] = {
    "kinematic": lambda: KinematicBackend(KinematicLimits(), N),
    "px4": lambda: Px4Backend(px4_vehicle_configs(KinematicLimits(), 4.0, [(2.0 * i, 0.0, 0.0) for i in range(N)])),
}


def none() -> list[VehicleRequest]:
    return [VehicleRequest.NONE] * N


@pytest.fixture(params=sorted(BACKENDS))
def backend(request: pytest.FixtureRequest) -> VehicleBackend:
    return BACKENDS[request.param]()


def assert_shapes(state: BackendState) -> None:
    assert state.vehicle_count == N
    assert state.position_ned_m.shape == state.velocity_ned_mps.shape == (N, 3)
    for array in (state.yaw_ned_rad, state.battery_fraction):
        assert array.shape == (N,) and array.dtype == np.float64
    for array in (state.armed, state.in_air, state.alive):
        assert array.shape == (N,) and array.dtype == np.bool_
    assert all(mode in MAVSDK_MODE_NAMES for mode in state.flight_mode)


def test_is_a_vehicle_backend_and_starts_on_the_pads(backend: VehicleBackend) -> None:
    assert isinstance(backend, VehicleBackend) and backend.vehicle_count == N
    before = backend.state()
    assert_shapes(before)
    assert before.t_s == 0.0 and not before.armed.any() and not before.in_air.any() and before.alive.all()
    assert before.flight_mode == ("AUTO.LOITER",) * N  # PX4 boots in Hold
    with pytest.raises(RuntimeError, match="hover_start"):
        backend.step(np.zeros((N, 3)), np.zeros(N), np.ones(N, bool), none(), DT_S)


def test_hover_start_once_then_states_are_values(backend: VehicleBackend) -> None:
    first = backend.hover_start(4.0)
    assert_shapes(first)
    assert first.t_s == 0.0 and first.armed.all() and first.in_air.all() and first.flight_mode == ("OFFBOARD",) * N
    with pytest.raises(RuntimeError, match="already"):
        backend.hover_start(4.0)
    position = first.position_ned_m.copy()
    later = backend.step(np.ones((N, 3)), np.zeros(N), np.ones(N, bool), none(), DT_S)
    assert later.t_s == pytest.approx(DT_S)
    np.testing.assert_array_equal(first.position_ned_m, position)  # a returned state never changes
    with pytest.raises(ValueError):
        first.position_ned_m[0, 0] = 1.0
    np.testing.assert_array_equal(backend.state().position_ned_m, later.position_ned_m)


def test_step_inputs_are_checked(backend: VehicleBackend) -> None:
    backend.hover_start(4.0)
    good = dict(velocity_setpoint_ned_mps=np.zeros((N, 3)), yaw_ned_rad=np.zeros(N), setpoint_sent=np.ones(N, bool),
                requests=none(), dt_s=DT_S)
    for bad in (
        dict(velocity_setpoint_ned_mps=np.zeros((N + 1, 3))),
        dict(yaw_ned_rad=np.zeros(N + 1)),
        dict(setpoint_sent=np.ones(N)),
        dict(requests=["land"] * N),
        dict(requests=none()[1:]),
        dict(dt_s=0.0),
    ):
        with pytest.raises(ValueError, match=next(iter(bad))):
            backend.step(**(good | bad))
    with pytest.raises(IndexError):
        backend.kill(N)


def test_kill_is_a_power_loss(backend: VehicleBackend) -> None:
    backend.hover_start(4.0)
    backend.kill(1)
    for _ in range(60):
        state = backend.step(np.zeros((N, 3)), np.zeros(N), np.ones(N, bool), none(), DT_S)
    assert list(state.alive) == [True, False, True] and list(state.armed) == [True, False, True]
    assert state.position_ned_m[1, 2] == 0.0 and not state.in_air[1]


def test_every_px4_mode_has_its_mavsdk_name() -> None:
    assert set(MAVSDK_MODE_NAMES) == {m.value for m in Px4Mode}
    assert MAVSDK_MODE_NAMES["OFFBOARD"] == "OFFBOARD" and MAVSDK_MODE_NAMES["AUTO.LOITER"] == "HOLD"


def test_a_vehicle_killed_before_the_start_stays_on_its_pad(backend: VehicleBackend) -> None:
    backend.kill(0)
    state = backend.hover_start(4.0)
    assert list(state.alive) == [False, True, True] and list(state.armed) == [False, True, True]
    assert state.position_ned_m[0, 2] == 0.0 and state.flight_mode[1:] == ("OFFBOARD", "OFFBOARD")
