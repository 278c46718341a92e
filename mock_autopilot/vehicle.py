"""One simulated PX4 vehicle, sans I/O: ``handle(link, message, now_s)`` and ``tick(now_s)`` return what to send.

This module is the vehicle's MAVLink front end: messages and commands go through dispatch tables to the
commander (:mod:`mock_autopilot.commander`: modes, arming, failsafes), the position controller
(:mod:`mock_autopilot.position_control`), the battery and the stream schedule, which share one
:class:`~mock_autopilot.vehicle_state.VehicleState`; telemetry is encoded from a frozen snapshot of that state.
The vehicle never touches a socket or a clock: the fleet's UDP links feed it decoded messages with the simulated
time and send what it returns (h11's shape). Physics is the pure kinematics of :mod:`mock_autopilot.kinematics`
(paper eqs 1-3 with PX4 limits from the parameters).

Interpretations worth knowing (the README of the package lists every acceptance rule with the PX4 behaviour it
follows):
* Every vehicle has odometry (a flow/vision-like local estimate), so the local position is always valid; GPS
  vehicles add a global position. Losing GPS removes the global position only; modes that need it
  (AUTO.RTL, AUTO.MISSION, DO_REPOSITION) then land, as PX4 does on global position loss.
* Without RC, the manual modes hold: POSCTL holds position, ALTCTL/STABILIZED/MANUAL stop and hold altitude.
  Arming in a manual mode is refused ("manual control lost"), so the boot mode is Hold (AUTO.LOITER).
* After an automatic landing and disarm the mode returns to Hold, as PX4 commander does.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
from pymavlink.dialects.v20 import common as mavlink

from comms.px4 import MavResult, Px4Mode
from mock_autopilot import commander, telemetry
from mock_autopilot.commander import SEVERITY_CRITICAL, SEVERITY_WARNING, text
from mock_autopilot.kinematics import KinematicState, step_kinematics
from mock_autopilot.position_control import fall, velocity_command, yaw_step
from mock_autopilot.px4_params import PARAM_INDEX, PARAM_SPECS, PARAM_TABLE, ParamError
from mock_autopilot.px4_params import decode_param_value, encode_param_value
from mock_autopilot.setpoints import decode_position_target
from mock_autopilot.telemetry import VehicleSnapshot
from mock_autopilot.vehicle_commands import COMMAND_HANDLERS
from mock_autopilot.vehicle_snapshot import take_snapshot
from mock_autopilot.vehicle_state import NO_ACCEL, Outgoing, VehicleConfig, VehicleState

__all__ = ["Outgoing", "Vehicle", "VehicleConfig"]

PHYSICS_STEP_S = 0.02
MAV_TYPE_GCS = mavlink.MAV_TYPE_GCS
_IGNORED_MESSAGES = frozenset({"COMMAND_ACK", "RADIO_STATUS", "SYSTEM_TIME", "STATUSTEXT", "MANUAL_CONTROL",
                               "REQUEST_DATA_STREAM", "PARAM_VALUE", "MISSION_ACK", "AUTOPILOT_VERSION"})
"""Messages a PX4 receives and has no answer to: counted as ``ignored``, not as ``unhandled``."""
_SETPOINT_REFUSALS_LOGGED = {
    "force_setpoint_unsupported": "SET_POSITION_TARGET_LOCAL_NED force not supported",
    "frame_unsupported": "SET_POSITION_TARGET_LOCAL_NED coordinate frame {frame} unsupported",
    "no_setpoint": "SET_POSITION_TARGET_LOCAL_NED invalid",
}
"""The setpoint refusals PX4's receiver announces as a critical STATUSTEXT (the rest it drops silently)."""


MessageHandler = Callable[["Vehicle", str, mavlink.MAVLink_message, float], list[Outgoing]]


class Vehicle(VehicleState):
    """A PX4 multicopter reduced to its MAVLink behaviour and a point-mass body."""

    # ------------------------------------------------------------------ read-only views
    @property
    def battery_voltage_v(self) -> float:
        return self.battery.voltage_v()

    @property
    def battery_current_a(self) -> float:
        return self.battery.current_a(self.armed)

    def arming_denial(self, now_s: float) -> str | None:
        """Why PX4 would refuse to arm now, or None (also the PREARM_CHECK health bit)."""
        return commander.arming_denial(self, now_s)

    def stream_rates_hz(self, link: str) -> dict[str, float]:
        """Message name -> rate [Hz, simulated] this vehicle streams on ``link`` now (after SET_MESSAGE_INTERVAL)."""
        return self.streams.rates_hz(link)

    def snapshot(self, now_s: float) -> VehicleSnapshot:
        """The frozen view telemetry is encoded from."""
        return take_snapshot(self, now_s)

    # ------------------------------------------------------------------ inbound
    def handle(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        """React to one decoded, target-checked message from ``link``; returns replies."""
        if self.killed:
            return []
        name = msg.get_type()
        handler = _MESSAGE_HANDLERS.get(name)
        if handler is None:
            self.handled["ignored" if name in _IGNORED_MESSAGES else "unhandled"] += 1
            return []
        self.handled[name] += 1
        return handler(self, link, msg, now_s)

    def _reject(self, reason: str) -> list[Outgoing]:
        self.rejections[reason] += 1
        return []

    def _on_heartbeat(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        if msg.type == MAV_TYPE_GCS:
            self.last_gcs_heartbeat_s = now_s
            self.datalink_lost = False
        return []

    def _on_ping(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        if msg.target_system != 0:
            return []
        reply = mavlink.MAVLink_ping_message(msg.time_usec, msg.seq, msg.get_srcSystem(), msg.get_srcComponent())
        return [Outgoing(link, reply)]

    def _on_timesync(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        if msg.tc1 != 0:
            return []
        return [Outgoing(link, mavlink.MAVLink_timesync_message(int(now_s * 1e9), msg.ts1))]

    def _on_mission_request_list(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        reply = mavlink.MAVLink_mission_count_message(msg.get_srcSystem(), msg.get_srcComponent(), 0, msg.mission_type)
        return [Outgoing(link, reply)]

    def _on_mission_clear_all(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        reply = mavlink.MAVLink_mission_ack_message(msg.get_srcSystem(), msg.get_srcComponent(), 0, msg.mission_type)
        return [Outgoing(link, reply)]

    # --- parameters
    def _param_value(self, index: int) -> mavlink.MAVLink_message:
        spec = PARAM_TABLE[index]
        wire = encode_param_value(self.params[spec.name], spec.type)
        return mavlink.MAVLink_param_value_message(spec.name.encode(), wire, int(spec.type), len(PARAM_TABLE), index)

    def _on_param_request_list(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        return [Outgoing(link, self._param_value(i)) for i in range(len(PARAM_TABLE))]

    def _on_param_request_read(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        if msg.param_index >= 0:
            if msg.param_index >= len(PARAM_TABLE):
                return self._reject("param_index_out_of_range")
            return [Outgoing(link, self._param_value(msg.param_index))]
        index = PARAM_INDEX.get(msg.param_id)
        if index is None:
            return self._reject("unknown_param")
        return [Outgoing(link, self._param_value(index))]

    def _on_param_set(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        spec = PARAM_SPECS.get(msg.param_id)
        if spec is None:
            self.rejections["unknown_param"] += 1
            return [Outgoing(link, telemetry.statustext(SEVERITY_WARNING, f"Param {msg.param_id[:30]} unknown"))]
        index = PARAM_INDEX[spec.name]
        try:
            value = decode_param_value(msg.param_value, msg.param_type, spec.type)
            self.params.set(spec.name, value)
        except ParamError as exc:
            self.rejections["bad_param_value"] += 1
            return [
                Outgoing(link, telemetry.statustext(SEVERITY_WARNING, f"Param rejected: {exc}")),
                Outgoing(link, self._param_value(index)),
            ]
        return [Outgoing(None, self._param_value(index))]

    # --- offboard setpoints
    def _on_position_target(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        decoded = decode_position_target(
            msg.coordinate_frame, msg.type_mask, (msg.x, msg.y, msg.z), (msg.vx, msg.vy, msg.vz),
            (msg.afx, msg.afy, msg.afz), msg.yaw, msg.yaw_rate, self.position_ned_m, self.yaw_rad,
        )
        if isinstance(decoded, str):
            self.rejections[f"setpoint_{decoded}"] += 1
            logged = _SETPOINT_REFUSALS_LOGGED.get(decoded)
            return [text(SEVERITY_CRITICAL, logged.format(frame=msg.coordinate_frame))] if logged else []
        if not decoded.flyable:
            self.rejections["setpoint_not_flyable"] += 1
        self.offboard_setpoint = decoded
        self.setpoint_t_s = now_s
        return []

    # --- modes
    def _on_set_mode(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        custom = msg.custom_mode
        if custom & 0xFFFF:  # bits PX4 never sets: no mode of PX4's
            self.rejections["unknown_mode"] += 1
            return [self._ack(link, msg, mavlink.MAV_CMD_DO_SET_MODE, MavResult.DENIED)]
        result, texts = commander.set_mode(self, msg.base_mode, (custom >> 16) & 0xFF, (custom >> 24) & 0xFF, now_s)
        return texts + [self._ack(link, msg, mavlink.MAV_CMD_DO_SET_MODE, result)]

    # --- commands
    def _ack(self, link: str, msg: mavlink.MAVLink_message, command: int, result: int) -> Outgoing:
        return Outgoing(
            link, mavlink.MAVLink_command_ack_message(command, result, 0, 0, msg.get_srcSystem(), msg.get_srcComponent())
        )

    def _on_command_int(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        params = [msg.param1, msg.param2, msg.param3, msg.param4, msg.x / 1e7, msg.y / 1e7, msg.z]
        relative_alt = msg.frame in (mavlink.MAV_FRAME_GLOBAL_RELATIVE_ALT, mavlink.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT)
        if msg.command == mavlink.MAV_CMD_DO_REPOSITION and msg.x == 0 and msg.y == 0:
            params[4] = params[5] = math.nan
        return self._command(link, msg, msg.command, params, now_s, relative_alt)

    def _on_command_long(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        params = [msg.param1, msg.param2, msg.param3, msg.param4, msg.param5, msg.param6, msg.param7]
        return self._command(link, msg, msg.command, params, now_s, False)

    def _command(
        self, link: str, msg: mavlink.MAVLink_message, command: int, p: list[float], now_s: float, relative_alt: bool
    ) -> list[Outgoing]:
        handler = COMMAND_HANDLERS.get(command)
        if handler is None:
            self.rejections["unsupported_command"] += 1
            return [self._ack(link, msg, command, MavResult.UNSUPPORTED)]
        reply = handler(self, link, command, p, now_s, relative_alt)
        if reply.result not in (MavResult.ACCEPTED, MavResult.UNSUPPORTED):
            self.rejections[f"command_{command}_result_{int(reply.result)}"] += 1
        return reply.before + [self._ack(link, msg, command, reply.result)] + reply.after

    # ------------------------------------------------------------------ faults (called by the fleet)
    def set_gps_available(self, available: bool, now_s: float) -> None:
        """Lose or regain the GPS (fault injection); only meaningful for a vehicle fitted with GPS."""
        if not self.config.has_gps or available == self.gps_available:
            return
        self.gps_available = available
        self.pending.append(text(SEVERITY_CRITICAL, "GPS regained" if available else "GPS lost: global position invalid"))

    def set_battery_remaining(self, fraction: float) -> None:
        """Drain (or refill) the battery to ``fraction`` of its capacity (fault injection)."""
        self.battery.set_remaining(fraction)

    def kill(self) -> None:
        """Power loss: the vehicle stops talking and falls (fault injection)."""
        self.killed = True
        self.armed = False

    # ------------------------------------------------------------------ time
    def tick(self, now_s: float) -> list[Outgoing]:
        """Advance physics and timers to ``now_s`` and return due telemetry and event messages."""
        while self.t_s < now_s - 1e-9:
            self._step(min(PHYSICS_STEP_S, now_s - self.t_s))
        if self.killed:
            self.pending.clear()
            return []
        out, self.pending = self.pending, []
        horizon = now_s + self.stream_slack_s + 1e-9
        if not self.streams.anything_due(horizon):
            return out
        snapshot: VehicleSnapshot | None = None
        built: dict[str, mavlink.MAVLink_message | None] = {}  # one message per stream and tick, shared by links
        for link, name in self.streams.take_due(now_s, horizon):
            if name not in built:
                snapshot = snapshot or take_snapshot(self, now_s)
                built[name] = telemetry.BUILDERS[name](snapshot)
            message = built[name]
            if message is not None:
                out.append(Outgoing(link, message))
        return out

    def _step(self, dt: float) -> None:
        t = self.t_s + dt
        if self.armed:
            command, yaw_target, yaw_rate = velocity_command(self, t)
            self.commanded_down_mps = float(command[2])
            if self.weather is not None:
                new_body = self._fly_in_weather(command, dt)
            else:
                wind = self.wind_ned if self.wind_ned is not None and not self.on_ground() else None
                new_body = step_kinematics(self.body, command, self.limits(), dt, wind_ned_mps=wind)
            max_rate = math.radians(self.params["MPC_YAWRAUTO_MAX"])
            self.yaw_rad, self.yaw_rate_rad_s = yaw_step(self.yaw_rad, yaw_target, yaw_rate, max_rate, dt)
        else:
            new_body = fall(self.body, self.on_ground(), dt)
            self.yaw_rate_rad_s = 0.0
        if self.weather is not None:
            if not self.armed:
                self.reference_velocity_ned_mps = new_body.velocity_ned_mps
            self.weather.sensor_step(self.t_s, dt, (new_body.position_ned_m - self.body.position_ned_m)[None, :])
            estimate, yaw = self.weather.estimate(new_body.position_ned_m[None, :], np.array([self.yaw_rad]))
            self.estimate_ned_m, self.estimate_yaw_rad = estimate[0], float(yaw[0])
        if new_body is not self.body:
            self.accel_ned = (new_body.velocity_ned_mps - self.body.velocity_ned_mps) / dt
            self.body = new_body
        elif self.accel_ned is not NO_ACCEL:
            self.accel_ned = NO_ACCEL
        self.t_s = t
        if self.armed:
            self.battery.drain(dt, self.params)
        self._update_ground(t)
        commander.check_timers(self, t)

    def _fly_in_weather(self, command: np.ndarray, dt: float) -> KinematicState:
        """The commanded (reference) motion of the kinematics plus what the wind adds against PX4's velocity loop
        (:mod:`mock_autopilot.wind_response`, the same laws the lockstep kinematics fly)."""
        weather = self.weather
        assert weather is not None
        body = self.body
        reference = step_kinematics(KinematicState(body.position_ned_m, self.reference_velocity_ned_mps), command,
                                    self.limits(), dt)
        accel = (reference.velocity_ned_mps - self.reference_velocity_ned_mps) / dt
        before = weather.disturbance.error_mps[0]
        airborne = np.array([not self.on_ground()])
        after = weather.air_step(self.t_s, dt, reference.velocity_ned_mps[None, :], accel[None, :], airborne)[0]
        position = reference.position_ned_m + 0.5 * (before + after) * dt
        position[2] = min(float(position[2]), 0.0)
        self.reference_velocity_ned_mps = reference.velocity_ned_mps
        return KinematicState(position_ned_m=position, velocity_ned_mps=reference.velocity_ned_mps + after)

    def _update_ground(self, t: float) -> None:
        """The land detector: on the ground without climb demand (or taking off) starts its timer."""
        climbing = self.armed and (self.commanded_down_mps < -0.1 or self.mode == Px4Mode.AUTO_TAKEOFF)
        if self.on_ground() and not climbing:
            if self.ground_since_s is None:
                self.ground_since_s = t
        else:
            self.ground_since_s = None
        if self.armed and float(self.body.position_ned_m[2]) < -0.5:  # the truth: altitude noise is no take-off
            self.took_off = True


_MESSAGE_HANDLERS: dict[str, MessageHandler] = {
    "HEARTBEAT": Vehicle._on_heartbeat,
    "COMMAND_LONG": Vehicle._on_command_long,
    "COMMAND_INT": Vehicle._on_command_int,
    "SET_MODE": Vehicle._on_set_mode,
    "SET_POSITION_TARGET_LOCAL_NED": Vehicle._on_position_target,
    "PARAM_REQUEST_LIST": Vehicle._on_param_request_list,
    "PARAM_REQUEST_READ": Vehicle._on_param_request_read,
    "PARAM_SET": Vehicle._on_param_set,
    "MISSION_REQUEST_LIST": Vehicle._on_mission_request_list,
    "MISSION_CLEAR_ALL": Vehicle._on_mission_clear_all,
    "PING": Vehicle._on_ping,
    "TIMESYNC": Vehicle._on_timesync,
}
"""Inbound message name -> handler; a name missing here is counted as ignored or unhandled."""
