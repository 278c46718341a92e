"""The sans-IO mock PX4 as a backend: every vehicle is a :class:`mock_autopilot.vehicle.Vehicle`, driven through
its MAVLink front end exactly as MAVSDK drives PX4, so a lockstep run flies PX4's commander modes and failsafes.

What goes in, per control period, at the vehicles' own time ``t``:

* a ground-station HEARTBEAT (MAV_TYPE_GCS) on the ``gcs`` link every ``gcs_heartbeat_period_s`` of simulated
  time, so PX4's datalink-loss rule (NAV_DLL_ACT after COM_DL_LOSS_T) sees a ground station, as in the processes
  engine;
* where ``setpoint_sent``: SET_POSITION_TARGET_LOCAL_NED on the ``onboard`` link, MAV_FRAME_LOCAL_NED with the
  velocity + yaw type mask MAVSDK's ``offboard.set_velocity_ned`` uses (2503; with a NaN yaw the yaw is left out
  too). PX4 treats every valid one as offboard proof of life; without them for COM_OF_LOSS_T it leaves OFFBOARD
  (COM_OBL_RC_ACT);
* a request as the message MAVSDK sends for it: ARM = COMMAND_LONG MAV_CMD_COMPONENT_ARM_DISARM(1), TAKEOFF =
  MAV_CMD_NAV_TAKEOFF (NaN parameters: PX4 climbs to MIS_TAKEOFF_ALT), START_OFFBOARD / HOLD = MAV_CMD_DO_SET_MODE
  with PX4's custom mode (OFFBOARD; AUTO.LOITER), LAND = MAV_CMD_NAV_LAND. Their COMMAND_ACK results are counted
  per vehicle (:meth:`Px4Backend.acks`), so a refused command is visible.

Then ``Vehicle.tick(t + dt)`` advances PX4's 50 Hz physics and timers. The vehicles' telemetry is dropped (only
STATUSTEXTs are kept, :meth:`Px4Backend.texts`): the backend reads their state directly, so they are built with the
``minimal`` stream profile (heartbeat only) and no telemetry message nobody reads is built.

``hover_start`` flies the real pre-mission sequence on the vehicles' clock (MAVSDK's order, as the onboard agents'
flight phase does): set MIS_TAKEOFF_ALT (PARAM_SET, as ``action.set_takeoff_altitude``), arm once PX4 allows it,
take off (AUTO.TAKEOFF ends in AUTO.LOITER at the altitude), wait for Hold to settle, stream zero setpoints and
switch to OFFBOARD, hover at least ``settle_s`` and until at rest. Mission time 0 is the vehicles' time at the end:
``BackendState.t_s`` is the vehicles' time minus that offset.
"""

from __future__ import annotations

import enum
import math
from collections import Counter, deque
from dataclasses import replace
from typing import Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pymavlink.dialects.v20 import common as mavlink

from comms.frames import GeodeticHome
from comms.px4 import MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, MAV_MODE_FLAG_SAFETY_ARMED, MODE_TABLE, LandedState, MavResult, Px4Mode
from mock_autopilot.backends.interface import BackendState, VehicleRequest, step_inputs
from mock_autopilot.dynamics_params import px4_params
from mock_autopilot.kinematics import KinematicLimits
from mock_autopilot.periodic_schedule import next_slot_s, slot_reached
from mock_autopilot.px4_params import PARAM_SPECS, encode_param_value
from mock_autopilot.px4_streams import GCS, ONBOARD
from mock_autopilot.setpoints import IGNORE_YAW, MASK_VELOCITY_AND_YAW, MAV_FRAME_LOCAL_NED
from mock_autopilot.vehicle import Outgoing, Vehicle, VehicleConfig
from mock_autopilot.weather_model import Weather

STREAM_PROFILE = "minimal"
AUTOPILOT_COMPONENT_ID = 1
GCS_HEARTBEAT_PERIOD_S = 1.0
SEQUENCE_PERIOD_S = 0.05
"""Period [s] of the pre-mission sequence's setpoints and checks: an agent's 20 Hz control loop."""
TEXTS_KEPT = 20
HOLD_SETTLED_M = 0.05
"""Altitude error [m] at which Hold counts as settled after the take-off, before switching to OFFBOARD."""
HOLD_SETTLED_MPS = 0.05
OFFBOARD_SETTLED_MPS = 0.001
"""Speed [m/s] below which the zero-setpoint OFFBOARD hover counts as at rest: mission time 0 then finds every
vehicle as the kinematic backend starts it, to millimetres (the residual decays with the response time)."""
WEATHER_SETTLE_S = 5.0
"""In weather a vehicle is never at rest (gusts, noisy estimate): each settling step then ends after this long
[s] at the latest."""


def px4_vehicle_configs(
    limits: KinematicLimits,
    takeoff_altitude_m: float,
    pads_enu_m: ArrayLike,
    *,
    has_gps: Sequence[bool] | None = None,
    home: GeodeticHome | None = None,
    params: Mapping[str, float] | None = None,
    system_ids: Sequence[int] | None = None,
    stream_profile: str = STREAM_PROFILE,
    weather: Weather | None = None,
) -> list[VehicleConfig]:
    """One :class:`VehicleConfig` per pad [m; (N,3) or (N,2) mission ENU], with the plan's dynamics as PX4 reads
    them: MPC_* from ``limits`` (:func:`mock_autopilot.dynamics_params.px4_params`) and the plant's
    ``response_time_s``; ``params`` overrides or adds PX4 parameters (e.g. COM_OBL_RC_ACT). ``system_ids`` default
    to PX4 SITL's instance + 1; ``stream_profile`` to this backend's minimal one (the fleet process streams
    telemetry to real clients and passes its own)."""
    pads = np.asarray(pads_enu_m, dtype=float)
    pads = pads.reshape(len(pads), -1)
    gps = [True] * len(pads) if has_gps is None else list(has_gps)
    if len(gps) != len(pads):
        raise ValueError(f"has_gps: expected {len(pads)} flags, got {len(gps)}")
    if system_ids is not None and len(system_ids) != len(pads):
        raise ValueError(f"system_ids: expected {len(pads)} ids, got {len(system_ids)}")
    merged = {**px4_params(limits, takeoff_altitude_m), **dict(params or {})}
    return [
        VehicleConfig(
            instance=i,
            has_gps=gps[i],
            pad_enu_m=(float(pad[0]), float(pad[1]), float(pad[2]) if len(pad) > 2 else 0.0),
            home=home if home is not None else GeodeticHome(),
            params=merged,
            response_time_s=limits.response_time_s,
            stream_profile=stream_profile,
            system_id=None if system_ids is None else int(system_ids[i]),
            weather=weather,
        )
        for i, pad in enumerate(pads)
    ]


class _Climb(enum.Enum):
    """Where one vehicle is in the pre-mission sequence."""

    ARM = "arm"
    TAKEOFF = "takeoff"
    CLIMB = "climb"
    OFFBOARD = "offboard"
    SETTLE = "settle"
    READY = "ready"


def _gcs_heartbeat() -> mavlink.MAVLink_message:
    return mavlink.MAVLink_heartbeat_message(
        mavlink.MAV_TYPE_GCS, mavlink.MAV_AUTOPILOT_INVALID, 0, 0, mavlink.MAV_STATE_ACTIVE, 3
    )


def _command_long(target_system: int, command: int, *params: float) -> mavlink.MAVLink_message:
    p = list(params) + [math.nan] * (7 - len(params))
    return mavlink.MAVLink_command_long_message(target_system, AUTOPILOT_COMPONENT_ID, command, 0, *p)


def _set_mode_command(target_system: int, mode: Px4Mode, armed: bool) -> mavlink.MAVLink_message:
    """MAV_CMD_DO_SET_MODE as MAVSDK sends it: base mode CUSTOM_MODE_ENABLED (| SAFETY_ARMED when armed), then
    PX4's main and sub mode."""
    spec = MODE_TABLE[mode]
    base = MAV_MODE_FLAG_CUSTOM_MODE_ENABLED | (MAV_MODE_FLAG_SAFETY_ARMED if armed else 0)
    return _command_long(
        target_system, mavlink.MAV_CMD_DO_SET_MODE, base, spec.main_mode, spec.sub_mode, 0.0, 0.0, 0.0, 0.0
    )


class Px4Backend:
    """N mock PX4 vehicles on one simulated clock, driven through MAVLink messages (see the module doc)."""

    def __init__(
        self,
        configs: Sequence[VehicleConfig],
        *,
        gcs_heartbeat_period_s: float = GCS_HEARTBEAT_PERIOD_S,
        settle_s: float = 1.0,
        hover_timeout_s: float = 120.0,
    ) -> None:
        if not configs:
            raise ValueError("configs: a fleet needs at least one vehicle")
        if not gcs_heartbeat_period_s > 0.0:
            raise ValueError(f"gcs_heartbeat_period_s: expected a positive period, got {gcs_heartbeat_period_s}")
        ids = [c.sysid for c in configs]
        if len(set(ids)) != len(ids):
            raise ValueError(f"configs: duplicate system ids {ids}")
        self.vehicles = [Vehicle(replace(c, stream_profile=STREAM_PROFILE), 0.0) for c in configs]
        self._n = len(self.vehicles)
        self.gcs_heartbeat_period_s = gcs_heartbeat_period_s
        self.settle_s = settle_s
        self.hover_timeout_s = hover_timeout_s
        self._vehicle_t_s = 0.0
        self._mission_offset_s = 0.0
        self._next_gcs_heartbeat_s = 0.0
        self._gcs_heartbeat = _gcs_heartbeat()
        self._acks: list[Counter[tuple[int, int]]] = [Counter() for _ in self.vehicles]
        self._texts: list[deque[str]] = [deque(maxlen=TEXTS_KEPT) for _ in self.vehicles]
        self._hold_since: list[float] = []
        self._started = False

    @property
    def vehicle_count(self) -> int:
        return self._n

    @property
    def vehicle_time_s(self) -> float:
        """The vehicles' own simulated time [s] since they booted (mission time + the pre-mission sequence)."""
        return self._vehicle_t_s

    def acks(self, index: int) -> Counter[tuple[int, int]]:
        """(MAV_CMD, MAV_RESULT) -> how many COMMAND_ACKs vehicle ``index`` answered so far (a copy)."""
        return Counter(self._acks[index])

    def texts(self, index: int) -> list[str]:
        """The newest STATUSTEXTs of vehicle ``index`` (PX4's words for failsafes, refusals, disarming)."""
        return list(self._texts[index])

    def rejections(self, index: int) -> Counter[str]:
        """Vehicle ``index``'s own count of refused input by reason (bad setpoints, refused commands; a copy)."""
        return Counter(self.vehicles[index].rejections)

    # ------------------------------------------------------------------ pre-mission sequence
    def hover_start(self, altitude_m: float) -> BackendState:
        """Fly every vehicle through arm, AUTO.TAKEOFF to ``altitude_m``, Hold, OFFBOARD (module doc); mission
        time 0 is the end. Raises RuntimeError naming the vehicles that did not get there in ``hover_timeout_s``."""
        if self._started:
            raise RuntimeError("hover_start: already called; a backend flies one mission")
        if not (math.isfinite(altitude_m) and altitude_m > 0.0):
            raise ValueError(f"altitude_m: expected a positive altitude, got {altitude_m}")
        self._started = True
        spec = PARAM_SPECS["MIS_TAKEOFF_ALT"]
        set_altitude = mavlink.MAVLink_param_set_message(
            0, AUTOPILOT_COMPONENT_ID, spec.name.encode(), encode_param_value(altitude_m, spec.type), int(spec.type)
        )
        for vehicle in self.vehicles:
            set_altitude.target_system = vehicle.system_id
            vehicle.handle(ONBOARD, set_altitude, self._vehicle_t_s)
            if vehicle.params["MIS_TAKEOFF_ALT"] != altitude_m:
                raise ValueError(f"altitude_m: vehicle {vehicle.system_id} refused MIS_TAKEOFF_ALT={altitude_m}")
        phases = [_Climb.READY if vehicle.killed else _Climb.ARM for vehicle in self.vehicles]  # the dead stay
        settled_at = [math.inf] * self._n
        self._hold_since = [math.inf] * self._n
        zero = np.zeros(3)
        deadline = self._vehicle_t_s + self.hover_timeout_s
        while not all(p is _Climb.READY for p in phases):
            t = self._vehicle_t_s
            if t > deadline:
                raise RuntimeError(f"hover_start: not hovering in OFFBOARD after {self.hover_timeout_s:g} s: "
                                   + self._describe_unready(phases))
            self._send_gcs_heartbeats(t)
            for i, vehicle in enumerate(self.vehicles):
                phases[i] = self._advance_climb(i, vehicle, phases[i], altitude_m, t)
                if phases[i] in (_Climb.OFFBOARD, _Climb.SETTLE, _Climb.READY) and not vehicle.killed:
                    vehicle.handle(ONBOARD, self._setpoint_message(vehicle, zero, vehicle.yaw_rad, t), t)
                if phases[i] is _Climb.OFFBOARD:
                    if self._request(i, VehicleRequest.START_OFFBOARD, t) == MavResult.ACCEPTED:
                        phases[i], settled_at[i] = _Climb.SETTLE, t + self.settle_s
                elif phases[i] is _Climb.SETTLE and t >= settled_at[i]:
                    waited = vehicle.weather is not None and t >= settled_at[i] + WEATHER_SETTLE_S
                    phases[i] = _Climb.READY if waited or self._at_rest(vehicle, OFFBOARD_SETTLED_MPS) else phases[i]
            self._tick(t + SEQUENCE_PERIOD_S)
        self._mission_offset_s = self._vehicle_t_s
        return self.state()

    def _advance_climb(self, i: int, vehicle: Vehicle, phase: _Climb, altitude_m: float, t: float) -> _Climb:
        if vehicle.killed:
            return phase
        if phase is not _Climb.ARM and not vehicle.armed:
            raise RuntimeError(f"hover_start: vehicle {vehicle.system_id} disarmed at {phase.value} "
                               f"({vehicle.mode.value}): {'; '.join(self._texts[i])}")
        if phase is _Climb.ARM and vehicle.arming_denial(t) is None:  # MAVSDK's health.is_armable (PREARM bit)
            if self._request(i, VehicleRequest.ARM, t) == MavResult.ACCEPTED:
                phase = _Climb.TAKEOFF
        if phase is _Climb.TAKEOFF and self._request(i, VehicleRequest.TAKEOFF, t) == MavResult.ACCEPTED:
            return _Climb.CLIMB
        if phase is _Climb.CLIMB and vehicle.mode is Px4Mode.AUTO_LOITER:
            self._hold_since[i] = min(self._hold_since[i], t)
            if vehicle.weather is not None and t >= self._hold_since[i] + WEATHER_SETTLE_S:
                return _Climb.OFFBOARD
            settled = abs(float(vehicle.position_ned_m[2]) + altitude_m) <= HOLD_SETTLED_M
            return _Climb.OFFBOARD if settled and self._at_rest(vehicle, HOLD_SETTLED_MPS) else phase
        return phase

    @staticmethod
    def _at_rest(vehicle: Vehicle, speed_mps: float) -> bool:
        return math.hypot(*(float(x) for x in vehicle.velocity_ned_mps)) <= speed_mps

    def _describe_unready(self, phases: Sequence[_Climb]) -> str:
        parts = []
        for vehicle, phase, texts in zip(self.vehicles, phases, self._texts):
            if phase is not _Climb.READY:
                parts.append(f"vehicle {vehicle.system_id} at {phase.value} ({vehicle.mode.value}, "
                             f"armed {vehicle.armed}, refusals {dict(vehicle.rejections)}, said {list(texts)})")
        return "; ".join(parts)

    # ------------------------------------------------------------------ mission
    def step(
        self,
        velocity_setpoint_ned_mps: NDArray[np.float64],
        yaw_ned_rad: NDArray[np.float64],
        setpoint_sent: NDArray[np.bool_],
        requests: Sequence[VehicleRequest],
        dt_s: float,
    ) -> BackendState:
        """One control period: heartbeat if due, setpoints, requests, then PX4's physics to ``t + dt_s``."""
        if not self._started:
            raise RuntimeError("step: call hover_start first")
        inputs = step_inputs(self._n, velocity_setpoint_ned_mps, yaw_ned_rad, setpoint_sent, requests, dt_s)
        t = self._vehicle_t_s
        self._send_gcs_heartbeats(t)
        sp, yaw, sent = inputs.velocity_setpoint_ned_mps, inputs.yaw_ned_rad, inputs.setpoint_sent
        for i, vehicle in enumerate(self.vehicles):
            if sent[i] and not vehicle.killed:
                vehicle.handle(ONBOARD, self._setpoint_message(vehicle, sp[i], float(yaw[i]), t), t)
        if inputs.any_request:
            for i, request in enumerate(inputs.requests):
                if request is not VehicleRequest.NONE:
                    self._request(i, request, t)
        self._tick(t + inputs.dt_s)
        return self.state()

    def _setpoint_message(self, vehicle: Vehicle, velocity_ned_mps: NDArray[np.float64], yaw_rad: float, t: float
                          ) -> mavlink.MAVLink_message:
        """SET_POSITION_TARGET_LOCAL_NED as MAVSDK's ``set_velocity_ned`` fills it (ignored fields zero)."""
        mask = MASK_VELOCITY_AND_YAW
        if math.isnan(yaw_rad):
            mask, yaw_rad = mask | IGNORE_YAW, 0.0
        return mavlink.MAVLink_set_position_target_local_ned_message(
            int(t * 1000.0) & 0xFFFFFFFF, vehicle.system_id, AUTOPILOT_COMPONENT_ID, MAV_FRAME_LOCAL_NED, mask,
            0.0, 0.0, 0.0, float(velocity_ned_mps[0]), float(velocity_ned_mps[1]), float(velocity_ned_mps[2]),
            0.0, 0.0, 0.0, yaw_rad, 0.0,
        )

    def _request(self, i: int, request: VehicleRequest, t: float) -> int | None:
        """Send ``request`` to vehicle ``i`` as MAVSDK would; returns the COMMAND_ACK result (None: no answer,
        e.g. a killed vehicle)."""
        vehicle = self.vehicles[i]
        sysid = vehicle.system_id
        if request is VehicleRequest.ARM:
            message = _command_long(sysid, mavlink.MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        elif request is VehicleRequest.TAKEOFF:
            message = _command_long(sysid, mavlink.MAV_CMD_NAV_TAKEOFF)
        elif request is VehicleRequest.START_OFFBOARD:
            message = _set_mode_command(sysid, Px4Mode.OFFBOARD, vehicle.armed)
        elif request is VehicleRequest.HOLD:
            message = _set_mode_command(sysid, Px4Mode.AUTO_LOITER, vehicle.armed)
        elif request is VehicleRequest.LAND:
            message = _command_long(sysid, mavlink.MAV_CMD_NAV_LAND)
        else:
            return None
        return self._count_acks(i, vehicle.handle(ONBOARD, message, t))

    def _count_acks(self, i: int, replies: list[Outgoing]) -> int | None:
        result = None
        for reply in replies:
            message = reply.message
            if message.get_type() == "COMMAND_ACK":
                self._acks[i][(int(message.command), int(message.result))] += 1
                result = int(message.result)
        return result

    def _send_gcs_heartbeats(self, t: float) -> None:
        if not slot_reached(self._next_gcs_heartbeat_s, t):
            return
        for vehicle in self.vehicles:
            vehicle.handle(GCS, self._gcs_heartbeat, t)
        self._next_gcs_heartbeat_s = next_slot_s(self._next_gcs_heartbeat_s, self.gcs_heartbeat_period_s, t)

    def _tick(self, t_s: float) -> None:
        """PX4's physics and timers to ``t_s``; of what they send only STATUSTEXTs are kept (module doc)."""
        for vehicle, texts in zip(self.vehicles, self._texts):
            for item in vehicle.tick(t_s):
                if item.message.get_type() == "STATUSTEXT":
                    text = item.message.text
                    texts.append(text.decode("ascii", "replace") if isinstance(text, bytes) else str(text))
        self._vehicle_t_s = t_s

    # ------------------------------------------------------------------ observation and faults
    def state(self) -> BackendState:
        vehicles = self.vehicles
        tilts = [v.tilt_rad() for v in vehicles]
        return BackendState.of(
            t_s=self._vehicle_t_s - self._mission_offset_s,
            position_ned_m=[v.body.position_ned_m for v in vehicles],
            velocity_ned_mps=[v.body.velocity_ned_mps for v in vehicles],
            yaw_ned_rad=[v.yaw_rad for v in vehicles],
            armed=[v.armed for v in vehicles],
            in_air=[v.landed_state is not LandedState.ON_GROUND for v in vehicles],
            flight_mode=[v.mode.value for v in vehicles],
            battery_fraction=[v.battery_remaining for v in vehicles],
            alive=[not v.killed for v in vehicles],
            estimated_position_ned_m=[v.position_ned_m for v in vehicles],
            estimated_yaw_ned_rad=[v.reported_yaw_rad for v in vehicles],
            roll_rad=[tilt[0] for tilt in tilts],
            pitch_rad=[tilt[1] for tilt in tilts],
        )

    def kill(self, index: int) -> None:
        """Power loss of vehicle ``index`` (``Vehicle.kill``): it stops answering and falls."""
        if not 0 <= index < self._n:
            raise IndexError(f"kill: vehicle {index} not in 0..{self._n - 1}")
        self.vehicles[index].kill()
