"""The lockstep engine's vehicle model as a backend: the paper's holonomic point with PX4 limits, over arrays.

Each armed vehicle follows :func:`mock_autopilot.kinematics.step_kinematics` (first-order velocity response with
``limits.response_time_s``, PX4's speed and acceleration clamps), computed for the whole fleet at once with numpy:
the lockstep engine steps up to 208 vehicles 20 times per simulated second, where one Python call per vehicle
costs more than the arithmetic (at 208 vehicles the batch is ~10x cheaper; below ~10 vehicles numpy's per-call
overhead makes it a few tens of microseconds per step dearer, which no mission notices; bench/vehicle_backends.py).
:func:`step_kinematics_batch` gives the same numbers as ``step_kinematics`` per vehicle (the same operations in the
same order; only ``hypot`` may differ in the last bit).

What it deliberately does not model (use :class:`mock_autopilot.backends.px4.Px4Backend` for these):

* No PX4 commander. After ``hover_start`` every vehicle stays armed, in air and in OFFBOARD. A vehicle without a
  setpoint keeps its previous one forever: there is no offboard-loss failsafe (COM_OF_LOSS_T), no datalink or
  battery failsafe, and the battery stays full.
* Requests: only LAND and HOLD act. LAND enters AUTO.LAND and descends at PX4's default MPC_LAND_SPEED holding
  zero horizontal velocity; at touch-down the vehicle disarms at once and PX4's mode after an automatic landing,
  AUTO.LOITER, follows (no land detector or COM_DISARM_LAND delay). HOLD enters AUTO.LOITER with a zero velocity
  setpoint: it stops where the velocity decays, about speed x response time beyond the point PX4's Hold would
  steer back to.
  Setpoints are ignored outside OFFBOARD, as PX4 does. ARM, TAKEOFF and START_OFFBOARD are ignored: take-off is
  not simulated here (``hover_start`` places the vehicles), and there is no way back to OFFBOARD.
* Yaw follows the setpoint's yaw at once (PX4 turns at up to MPC_YAWRAUTO_MAX); a NaN yaw keeps the heading.
* A killed (power-lost) vehicle falls as the mock PX4's does (:func:`fall_batch`).

Weather (``weather``, not calm): the commanded motion above is each vehicle's reference; the wind and PX4's
velocity loop fighting it add to it (:class:`mock_autopilot.weather_model.WeatherModel`, the same laws the mock
PX4 flies), the state reports the estimator's position and heading beside the truth, and the true tilt.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from comms.px4 import Px4Mode
from mock_autopilot.backends.interface import BackendState, VehicleRequest, read_only, step_inputs
from mock_autopilot.kinematics import KinematicLimits
from mock_autopilot.px4_params import PARAM_SPECS
from mock_autopilot.vehicle_state import GRAVITY_MPS2, GROUND_TOLERANCE_M
from mock_autopilot.weather_model import Weather, WeatherModel, velocity_loop_gains

LAND_SPEED_MPS = PARAM_SPECS["MPC_LAND_SPEED"].default
"""PX4's default MPC_LAND_SPEED [m/s]: the descent speed of AUTO.LAND (the mock PX4 reads the same default)."""
MAX_FALL_SPEED_MPS = 30.0
TWO_PI = 2.0 * math.pi


def step_kinematics_batch(
    position_ned_m: NDArray[np.float64],
    velocity_ned_mps: NDArray[np.float64],
    velocity_setpoint_ned_mps: NDArray[np.float64],
    limits: KinematicLimits,
    dt_s: float,
    ground_down_m: float = 0.0,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``step_kinematics`` for (M,3) rows at once: new (position [m NED], velocity [m/s NED]); no wind.

    Every line mirrors one of ``step_kinematics`` (setpoint clamp, first-order response, acceleration clamp,
    trapezoidal position, ground), so the two agree to rounding; tests/mock_autopilot/backends hold that.
    """
    if dt_s <= 0.0:
        return position_ned_m.copy(), velocity_ned_mps.copy()
    sp = velocity_setpoint_ned_mps
    change = sp.copy()  # the clamped setpoint first, then the velocity change towards it (one buffer)
    max_xy = limits.max_xy_speed_mps
    if max_xy > 0.0:
        xy = np.hypot(sp[:, 0], sp[:, 1])
        over = xy > max_xy
        if over.any():
            change[over, :2] *= (max_xy / xy[over])[:, None]
    change[:, 2] = np.minimum(np.maximum(sp[:, 2], -limits.max_climb_speed_mps), limits.max_descent_speed_mps)
    v = velocity_ned_mps
    alpha = 1.0 - math.exp(-dt_s / max(limits.response_time_s, 1e-6))
    change -= v
    change *= alpha
    dv_xy = np.hypot(change[:, 0], change[:, 1])
    max_dv_xy = limits.max_xy_accel_mps2 * dt_s
    over = dv_xy > max_dv_xy
    if over.any():
        change[over, :2] *= (max_dv_xy / dv_xy[over])[:, None]
    max_dv_z = limits.max_z_accel_mps2 * dt_s
    change[:, 2] = np.minimum(np.maximum(change[:, 2], -max_dv_z), max_dv_z)
    new_velocity = v + change
    new_position = position_ned_m + 0.5 * (v + new_velocity) * dt_s
    below = new_position[:, 2] > ground_down_m
    if below.any():
        new_position[below, 2] = ground_down_m
        new_velocity[below, 2] = np.minimum(new_velocity[below, 2], 0.0)
    return new_position, new_velocity


def fall_batch(
    position_ned_m: NDArray[np.float64], velocity_ned_mps: NDArray[np.float64], dt_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Unpowered (M,3) rows: the mock PX4's fall (``Vehicle._fall``): horizontal drag, gravity up to 30 m/s,
    resting on the ground once there."""
    p, v = position_ned_m, velocity_ned_mps
    resting = (p[:, 2] >= -GROUND_TOLERANCE_M) & (v[:, 2] <= 0.0)
    drag = math.exp(-dt_s)
    fall_mps = np.minimum(v[:, 2] + GRAVITY_MPS2 * dt_s, MAX_FALL_SPEED_MPS)
    new_v = np.column_stack((v[:, 0] * drag, v[:, 1] * drag, fall_mps))
    new_p = p + new_v * dt_s
    landed = resting | (new_p[:, 2] > 0.0)
    new_p[landed, 2] = 0.0
    new_v[landed] = 0.0
    new_p[resting, :2] = p[resting, :2]
    return new_p, new_v


def _with(array: NDArray[np.generic], where: int | NDArray[np.bool_], value: object) -> NDArray[np.generic]:
    """A read-only copy of ``array`` with ``array[where] = value``: states share the backend's arrays, so they are
    replaced, never written."""
    changed = array.copy()
    changed[where] = value
    return read_only(changed)


class KinematicBackend:
    """N holonomic points with PX4 limits: what the lockstep engine flies by default (see the module doc).

    Its arrays are read-only and replaced on every change, so a returned :class:`BackendState` shares them without
    copies (a copy of seven arrays per step would cost more than the physics).
    """

    def __init__(self, limits: KinematicLimits, n: int, weather: Weather | None = None,
                 vehicle_ids: Sequence[int] | None = None, has_gps: Sequence[bool] | None = None) -> None:
        if n < 1:
            raise ValueError(f"n: a fleet needs at least one vehicle, got {n}")
        self.limits = limits
        self._n = n
        ids = list(vehicle_ids) if vehicle_ids is not None else list(range(1, n + 1))
        gps = list(has_gps) if has_gps is not None else [True] * n
        self.weather = None if weather is None or weather.calm else WeatherModel(
            weather, ids, velocity_loop_gains(lambda name: PARAM_SPECS[name].default), gps)
        self._reference = read_only(np.zeros((n, 3)))
        self._estimate: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
        self._tilt: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
        self._t_s = 0.0
        self._position = read_only(np.zeros((n, 3)))
        self._velocity = read_only(np.zeros((n, 3)))
        self._setpoint = read_only(np.zeros((n, 3)))
        self._yaw = read_only(np.zeros(n))
        self._armed = read_only(np.zeros(n, dtype=bool))
        self._alive = read_only(np.ones(n, dtype=bool))
        self._battery = read_only(np.ones(n))
        self._modes: list[Px4Mode] = [Px4Mode.AUTO_LOITER] * n
        self._mode_names = tuple(m.value for m in self._modes)
        self._offboard = np.zeros(n, dtype=bool)
        self._landing = np.zeros(n, dtype=bool)
        self._all_offboard = False
        self._started = False

    @property
    def vehicle_count(self) -> int:
        return self._n

    def hover_start(self, altitude_m: float) -> BackendState:
        """Place every live vehicle ``altitude_m`` above its pad, armed in OFFBOARD at rest; mission time 0."""
        if self._started:
            raise RuntimeError("hover_start: already called; a backend flies one mission")
        if not (math.isfinite(altitude_m) and altitude_m > 0.0):
            raise ValueError(f"altitude_m: expected a positive altitude, got {altitude_m}")
        self._started = True
        self._t_s = 0.0
        hover = np.tile([0.0, 0.0, -altitude_m], (self._n, 1))
        self._position = read_only(np.where(self._alive[:, None], hover, self._position))  # the dead stay
        self._velocity = read_only(np.zeros((self._n, 3)))
        self._reference = self._velocity
        self._armed = self._alive
        if self.weather is not None:
            self._observe()
        self._set_modes([Px4Mode.OFFBOARD if alive else mode for alive, mode in zip(self._alive, self._modes)])
        return self.state()

    def step(
        self,
        velocity_setpoint_ned_mps: NDArray[np.float64],
        yaw_ned_rad: NDArray[np.float64],
        setpoint_sent: NDArray[np.bool_],
        requests: Sequence[VehicleRequest],
        dt_s: float,
    ) -> BackendState:
        """One control period (module doc: what is and is not modelled)."""
        if not self._started:
            raise RuntimeError("step: call hover_start first")
        inputs = step_inputs(self._n, velocity_setpoint_ned_mps, yaw_ned_rad, setpoint_sent, requests, dt_s)
        self._take_setpoints(inputs.velocity_setpoint_ned_mps, inputs.yaw_ned_rad, inputs.setpoint_sent)
        if inputs.any_request:
            self._apply_requests(inputs.requests)
        if self._all_offboard:
            command = self._setpoint
        else:
            command = np.where(self._offboard[:, None], self._setpoint, 0.0)
            command[self._landing] = (0.0, 0.0, LAND_SPEED_MPS)
        flying = self._armed
        if flying.all():
            position, reference = step_kinematics_batch(
                self._position, self._reference, command, self.limits, inputs.dt_s
            )
        else:
            position, reference = self._position.copy(), self._reference.copy()
            if flying.any():
                position[flying], reference[flying] = step_kinematics_batch(
                    position[flying], reference[flying], command[flying], self.limits, inputs.dt_s
                )
            idle = ~flying
            position[idle], reference[idle] = fall_batch(position[idle], self._velocity[idle], inputs.dt_s)
        velocity = reference
        if self.weather is not None:
            position, velocity = self._in_weather(position, reference, inputs.dt_s)
        self._position, self._velocity = read_only(position), read_only(velocity)
        self._reference = read_only(reference)
        if self._landing.any():
            self._disarm_touched_down()
        self._t_s += inputs.dt_s
        if self.weather is not None:
            self._observe()
        return self.state()

    def _in_weather(self, position: NDArray[np.float64], reference: NDArray[np.float64], dt_s: float
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The commanded motion plus what the wind adds (module doc); the estimator follows the truth."""
        weather = self.weather
        assert weather is not None
        airborne = self._armed & (self._position[:, 2] < -GROUND_TOLERANCE_M)
        accel = (reference - self._reference) / dt_s
        error_before = weather.disturbance.error_mps
        error = weather.air_step(self._t_s, dt_s, reference, accel, airborne)
        position = position + 0.5 * (error_before + error) * dt_s
        below = position[:, 2] > 0.0
        position[below, 2] = 0.0
        weather.sensor_step(self._t_s, dt_s, position - self._position)
        return position, reference + error

    def _observe(self) -> None:
        """The estimator's view and the tilt of the current truth."""
        weather = self.weather
        assert weather is not None
        self._estimate = tuple(read_only(a) for a in weather.estimate(self._position, self._yaw))  # type: ignore[assignment]
        self._tilt = tuple(read_only(a) for a in weather.tilt_rad(self._yaw))  # type: ignore[assignment]

    def _take_setpoints(self, setpoint: NDArray[np.float64], yaw: NDArray[np.float64], sent: NDArray[np.bool_]) -> None:
        """Keep the setpoints PX4 would accept: sent, finite (PX4 refuses a non-finite used field and flies the
        previous one) and, here, only in OFFBOARD."""
        if self._all_offboard and sent.all() and np.isfinite(setpoint).all():
            self._setpoint = read_only(setpoint.copy())
            if np.isfinite(yaw).all():
                self._yaw = read_only(np.mod(yaw, TWO_PI))
            else:
                turn = np.isfinite(yaw)
                self._yaw = _with(self._yaw, turn, np.mod(yaw[turn], TWO_PI))
            return
        accepted = sent & self._offboard & np.isfinite(setpoint).all(axis=1)
        if accepted.any():
            self._setpoint = _with(self._setpoint, accepted, setpoint[accepted])
            turn = accepted & np.isfinite(yaw)
            self._yaw = _with(self._yaw, turn, np.mod(yaw[turn], TWO_PI))

    def _apply_requests(self, requests: Sequence[VehicleRequest]) -> None:
        modes = list(self._modes)
        for i, request in enumerate(requests):
            if not self._armed[i]:
                continue
            if request is VehicleRequest.LAND:
                modes[i] = Px4Mode.AUTO_LAND
            elif request is VehicleRequest.HOLD:
                modes[i] = Px4Mode.AUTO_LOITER
        self._set_modes(modes)

    def _disarm_touched_down(self) -> None:
        touched_down = self._landing & self._armed & (self._position[:, 2] >= 0.0)
        if touched_down.any():
            self._armed = _with(self._armed, touched_down, False)
            self._set_modes([Px4Mode.AUTO_LOITER if down else mode for down, mode in zip(touched_down, self._modes)])

    def _set_modes(self, modes: list[Px4Mode]) -> None:
        self._modes = modes
        self._mode_names = tuple(m.value for m in modes)
        self._offboard = np.array([m is Px4Mode.OFFBOARD for m in modes]) & self._alive
        self._landing = np.array([m is Px4Mode.AUTO_LAND for m in modes]) & self._alive
        self._all_offboard = bool(self._offboard.all())

    def state(self) -> BackendState:
        return BackendState(
            t_s=self._t_s,
            position_ned_m=self._position,
            velocity_ned_mps=self._velocity,
            yaw_ned_rad=self._yaw,
            armed=self._armed,
            in_air=read_only(self._position[:, 2] < -GROUND_TOLERANCE_M),
            flight_mode=self._mode_names,
            battery_fraction=self._battery,
            alive=self._alive,
            estimated_position_ned_m=None if self._estimate is None else self._estimate[0],
            estimated_yaw_ned_rad=None if self._estimate is None else self._estimate[1],
            roll_rad=None if self._tilt is None else self._tilt[0],
            pitch_rad=None if self._tilt is None else self._tilt[1],
        )

    def kill(self, index: int) -> None:
        """Power loss of vehicle ``index``: disarmed, deaf to setpoints and requests, falling (its mode stays what
        it was, as the mock PX4's does)."""
        if not 0 <= index < self._n:
            raise IndexError(f"kill: vehicle {index} not in 0..{self._n - 1}")
        self._alive = _with(self._alive, index, False)
        self._armed = _with(self._armed, index, False)
        self._set_modes(self._modes)
