"""One simulated PX4 vehicle, sans I/O: ``handle(link, message, now_s)`` and ``tick(now_s)`` return what to send.

The vehicle never touches a socket or a clock: the fleet's UDP links feed it decoded messages with the
simulated time and send what it returns (h11's shape). Physics is the pure kinematics of
:mod:`mock_autopilot.kinematics` (paper eqs 1-3 with PX4 limits from the parameters); modes, failsafes and timers
follow PX4 commander as PX4_INTERFACE.md describes.

Interpretations worth knowing (documented in docs of the package too):
* Every vehicle has odometry (a flow/vision-like local estimate), so the local position is always valid; GPS
  vehicles add a global position. Losing GPS removes the global position only; modes that need it
  (AUTO.RTL, AUTO.MISSION, DO_REPOSITION) then land, as PX4 does on global position loss.
* Without RC, the manual modes hold: POSCTL holds position, ALTCTL/STABILIZED/MANUAL stop and hold altitude.
  Arming in a manual mode is refused ("manual control lost"), so the boot mode is Hold (AUTO.LOITER).
* After an automatic landing and disarm the mode returns to Hold, as PX4 commander does.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field, replace
from enum import IntEnum
from typing import Callable, Mapping

import numpy as np
from numpy.typing import NDArray
from pymavlink.dialects.v20 import common as mavlink

from comms.frames import GeodeticHome, geodetic_to_enu, mission_enu_to_local_ned
from mock_autopilot import telemetry
from mock_autopilot.kinematics import KinematicLimits, KinematicState, step_kinematics
from mock_autopilot.px4_failsafes import (
    BATTERY_LEVELS,
    DATALINK_LOSS_ACTIONS,
    DISARM,
    OFFBOARD_LOSS_ACTIONS,
    TERMINATE,
    FailsafeAction,
    battery_action,
)
from mock_autopilot.px4_modes import MODE_TABLE, Px4Mode, mode_allowed, mode_from_custom_mode, mode_from_numbers
from mock_autopilot.px4_params import PARAM_INDEX, PARAM_SPECS, PARAM_TABLE, ParamError, ParamStore
from mock_autopilot.px4_params import decode_param_value, encode_param_value
from mock_autopilot.px4_streams import DEFAULT_PROFILE, LINKS, stream_periods_s
from mock_autopilot.setpoints import OffboardSetpoint, decode_position_target, velocity_command_ned

PHYSICS_STEP_S = 0.02
LAND_DETECT_S = 0.5
GROUND_TOLERANCE_M = 0.05
TAKEOFF_ACCEPT_M = 0.2
GRAVITY_MPS2 = 9.81
FORCE_DISARM_MAGIC = 21196
BATTERY_CELLS = 4
HOVER_CURRENT_A = 15.0

_NO_ACCEL = np.zeros(3)
_NO_ACCEL.flags.writeable = False

MAV_RESULT_ACCEPTED = 0
MAV_RESULT_TEMPORARILY_REJECTED = 1
MAV_RESULT_DENIED = 2
MAV_RESULT_UNSUPPORTED = 3
MAV_RESULT_FAILED = 4

SEVERITY_CRITICAL = 2
SEVERITY_WARNING = 4
SEVERITY_INFO = 6
MAV_TYPE_GCS = 6


class LandedState(IntEnum):
    """MAV_LANDED_STATE values in EXTENDED_SYS_STATE."""

    ON_GROUND = 1
    IN_AIR = 2
    TAKEOFF = 3
    LANDING = 4


@dataclass(frozen=True)
class VehicleConfig:
    """How one vehicle is built: instance i has system id i+1 (PX4 SITL), a pad, GPS or not, parameters.

    pad_enu_m [m; mission ENU] is where the vehicle boots (its local NED origin) relative to ``home`` (the mission
    origin); a GPS vehicle reports GLOBAL_POSITION_INT = home + pad + local position.
    """

    instance: int
    has_gps: bool = True
    pad_enu_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    home: GeodeticHome = field(default_factory=GeodeticHome)
    params: Mapping[str, float] = field(default_factory=dict)
    initial_yaw_rad: float = 0.0
    wind_ned_mps: tuple[float, float, float] = (0.0, 0.0, 0.0)
    response_time_s: float = 0.3
    """First-order time constant of the velocity loop [s] (the plant, not a PX4 parameter): the same
    ``kinematics.response_time_s`` the lockstep kinematics read."""
    stream_profile: str = DEFAULT_PROFILE
    system_id: int | None = None

    @property
    def sysid(self) -> int:
        """MAVLink system id (instance + 1 unless given)."""
        return self.system_id if self.system_id is not None else self.instance + 1


@dataclass(frozen=True)
class Outgoing:
    """A message to send on one link (``link`` None: on every link)."""

    link: str | None
    message: mavlink.MAVLink_message


def _pad3(values: tuple[float, ...] | NDArray[np.float64]) -> tuple[float, float, float]:
    v = tuple(float(x) for x in values)
    return (v[0], v[1], v[2] if len(v) > 2 else 0.0)


class Vehicle:
    """A PX4 multicopter reduced to its MAVLink behaviour and a point-mass body."""

    def __init__(self, config: VehicleConfig, now_s: float = 0.0) -> None:
        pad = _pad3(config.pad_enu_m)
        if config.pad_enu_m != pad:
            config = replace(config, pad_enu_m=pad)
        self.config = config
        self.system_id = config.sysid
        self.params = ParamStore({"MAV_SYS_ID": self.system_id, **dict(config.params)})
        self.boot_time_s = now_s
        self.ground_below_enu_m = 0.0
        """Ground height below the vehicle above the home ground [m], set by the simulator (DISTANCE_SENSOR)."""
        self._t_s = now_s
        self.body = KinematicState()
        self.yaw_rad = float(config.initial_yaw_rad)
        self.yaw_rate_rad_s = 0.0
        self._accel_ned = _NO_ACCEL
        self.armed = False
        self.mode = Px4Mode.AUTO_LOITER
        self.failsafe = False
        self.killed = False
        self.gps_available = config.has_gps
        self.battery_remaining = 1.0
        self.battery_consumed_mah = 0.0
        self._battery_level_reported = 0
        self.home_ned_m = np.zeros(3)
        self.home_valid = config.has_gps
        self._hold_ned = np.zeros(3)
        self._takeoff_down_m = 0.0
        self._rtl_phase = "climb"
        self._cruise_speed_mps: float | None = None
        self.offboard_setpoint: OffboardSetpoint | None = None
        self._setpoint_t_s = -math.inf
        self._arm_t_s = now_s
        self._took_off = False
        self._ground_since_s: float | None = now_s
        self._commanded_down_mps = 0.0
        self._last_gcs_heartbeat_s: float | None = None
        self._datalink_lost = False
        self.rejections: Counter[str] = Counter()
        self.handled: Counter[str] = Counter()
        self._pending: list[Outgoing] = []
        self._periods: dict[str, dict[str, float]] = {
            link: stream_periods_s(config.stream_profile, link) for link in LINKS
        }
        self._next_due: dict[str, dict[str, float]] = {
            link: {name: now_s for name in periods} for link, periods in self._periods.items()
        }
        self._stream_epoch_s = now_s  # every stream is due on multiples of its period from here (see tick)
        self._limits_version = -1
        self._limits_cache = KinematicLimits()
        self._wind_ned = np.asarray(config.wind_ned_mps, dtype=float) if any(config.wind_ned_mps) else None
        self._battery_checked = math.nan
        self.stream_slack_s = 0.0  # the fleet sets half its tick: a message due within it goes out this tick
        self.geodetic_cache: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None
        self._earliest_due: dict[str, float] = {link: now_s for link in LINKS}
        self._handlers: dict[str, Callable[[str, mavlink.MAVLink_message, float], list[Outgoing]]] = {
            "HEARTBEAT": self._on_heartbeat,
            "COMMAND_LONG": self._on_command_long,
            "COMMAND_INT": self._on_command_int,
            "SET_MODE": self._on_set_mode,
            "SET_POSITION_TARGET_LOCAL_NED": self._on_position_target,
            "PARAM_REQUEST_LIST": self._on_param_request_list,
            "PARAM_REQUEST_READ": self._on_param_request_read,
            "PARAM_SET": self._on_param_set,
            "MISSION_REQUEST_LIST": self._on_mission_request_list,
            "MISSION_CLEAR_ALL": self._on_mission_clear_all,
            "PING": self._on_ping,
            "TIMESYNC": self._on_timesync,
        }
        self._ignored = frozenset(
            {"COMMAND_ACK", "RADIO_STATUS", "SYSTEM_TIME", "STATUSTEXT", "MANUAL_CONTROL", "REQUEST_DATA_STREAM",
             "PARAM_VALUE", "MISSION_ACK", "AUTOPILOT_VERSION"}
        )

    # ------------------------------------------------------------------ read-only views
    @property
    def position_ned_m(self) -> NDArray[np.float64]:
        """Position [m; local NED from the pad]."""
        return self.body.position_ned_m

    @property
    def velocity_ned_mps(self) -> NDArray[np.float64]:
        """Velocity [m/s; NED]."""
        return self.body.velocity_ned_mps

    @property
    def local_position_valid(self) -> bool:
        return not self.killed

    @property
    def global_position_valid(self) -> bool:
        return self.config.has_gps and self.gps_available and not self.killed

    @property
    def landed_state(self) -> LandedState:
        on_ground = self._ground_since_s is not None and self._t_s - self._ground_since_s >= LAND_DETECT_S
        if not self.armed:
            return LandedState.ON_GROUND if self._on_ground() else LandedState.IN_AIR
        if self.mode == Px4Mode.AUTO_TAKEOFF:
            return LandedState.TAKEOFF
        if (self.mode == Px4Mode.AUTO_LAND or (self.mode == Px4Mode.AUTO_RTL and self._rtl_phase == "land")) and not on_ground:
            return LandedState.LANDING
        return LandedState.ON_GROUND if on_ground else LandedState.IN_AIR

    @property
    def battery_voltage_v(self) -> float:
        return BATTERY_CELLS * (3.5 + 0.7 * max(0.0, self.battery_remaining))

    @property
    def battery_current_a(self) -> float:
        return HOVER_CURRENT_A if self.armed else 0.5

    @property
    def setpoint_received_s(self) -> float:
        """Simulated time [s] the newest valid offboard setpoint arrived (-inf before the first)."""
        return self._setpoint_t_s

    def offboard_fresh(self, now_s: float) -> bool:
        """Offboard proof of life: the newest valid setpoint is younger than COM_OF_LOSS_T."""
        return now_s - self._setpoint_t_s <= self.params["COM_OF_LOSS_T"]

    def tilt_rad(self) -> tuple[float, float]:
        """(roll, pitch) a multicopter would show for the current horizontal acceleration."""
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        a_forward = c * self._accel_ned[0] + s * self._accel_ned[1]
        a_right = -s * self._accel_ned[0] + c * self._accel_ned[1]
        return float(math.atan2(a_right, GRAVITY_MPS2)), float(-math.atan2(a_forward, GRAVITY_MPS2))

    def arming_denial(self, now_s: float) -> str | None:
        """Why PX4 would refuse to arm now, or None (also the PREARM_CHECK health bit)."""
        if self.killed:
            return "vehicle killed"
        if self.failsafe:
            return "failsafe active"
        if not self.local_position_valid:
            return "no local position"
        if self.config.has_gps and not self.gps_available and self.params.get_int("COM_ARM_WO_GPS") == 0:
            return "GPS fix required"
        if MODE_TABLE[self.mode].manual:
            return "manual control lost"
        if not mode_allowed(self.mode, self.local_position_valid, self.global_position_valid):
            return f"{self.mode.value} needs a global position"
        if self.mode == Px4Mode.OFFBOARD and not self.offboard_fresh(now_s):
            return "no offboard signal"
        if self.battery_remaining < self.params["BAT_EMERGEN_THR"]:
            return "battery too low"
        return None

    # ------------------------------------------------------------------ inbound
    def handle(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        """React to one decoded, target-checked message from ``link``; returns replies."""
        if self.killed:
            return []
        name = msg.get_type()
        handler = self._handlers.get(name)
        if handler is None:
            self.handled["ignored" if name in self._ignored else "unhandled"] += 1
            return []
        self.handled[name] += 1
        return handler(link, msg, now_s)

    def _reject(self, reason: str) -> list[Outgoing]:
        self.rejections[reason] += 1
        return []

    def _on_heartbeat(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        if msg.type == MAV_TYPE_GCS:
            self._last_gcs_heartbeat_s = now_s
            self._datalink_lost = False
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
            return self._reject(f"setpoint_{decoded}")
        self.offboard_setpoint = decoded
        self._setpoint_t_s = now_s
        return []

    # --- modes
    def _on_set_mode(self, link: str, msg: mavlink.MAVLink_message, now_s: float) -> list[Outgoing]:
        if not msg.base_mode & 1:
            self.rejections["set_mode_without_custom_flag"] += 1
            return [self._ack(link, msg, mavlink.MAV_CMD_DO_SET_MODE, MAV_RESULT_DENIED)]
        mode = mode_from_custom_mode(msg.custom_mode)
        if mode is None:
            self.rejections["unknown_mode"] += 1
            return [self._ack(link, msg, mavlink.MAV_CMD_DO_SET_MODE, MAV_RESULT_DENIED)]
        result, texts = self._request_mode(mode, now_s)
        return texts + [self._ack(link, msg, mavlink.MAV_CMD_DO_SET_MODE, result)]

    def _request_mode(self, mode: Px4Mode, now_s: float) -> tuple[int, list[Outgoing]]:
        if mode == self.mode:
            return MAV_RESULT_ACCEPTED, []
        if not mode_allowed(mode, self.local_position_valid, self.global_position_valid):
            return MAV_RESULT_TEMPORARILY_REJECTED, [self._text(SEVERITY_CRITICAL, f"Switching to {mode.value} is currently not possible")]
        if mode == Px4Mode.AUTO_MISSION:
            return MAV_RESULT_TEMPORARILY_REJECTED, [self._text(SEVERITY_CRITICAL, "Mission rejected: no mission")]
        if mode == Px4Mode.OFFBOARD and self.armed and not self.offboard_fresh(now_s):
            return MAV_RESULT_TEMPORARILY_REJECTED, [self._text(SEVERITY_CRITICAL, "Switching to Offboard is currently not possible")]
        if mode == Px4Mode.AUTO_TAKEOFF and not self.armed:
            return MAV_RESULT_TEMPORARILY_REJECTED, [self._text(SEVERITY_CRITICAL, "Takeoff denied: disarmed")]
        self._enter_mode(mode)
        self.failsafe = False
        return MAV_RESULT_ACCEPTED, []

    def _enter_mode(self, mode: Px4Mode) -> None:
        self.mode = mode
        if mode in (Px4Mode.AUTO_LOITER, Px4Mode.AUTO_READY, Px4Mode.POSCTL, Px4Mode.ALTCTL, Px4Mode.STABILIZED, Px4Mode.MANUAL):
            self._hold_ned = self.position_ned_m.copy()
        if mode == Px4Mode.AUTO_RTL:
            self._rtl_phase = "climb"
        if mode == Px4Mode.AUTO_TAKEOFF:
            self._hold_ned = self.position_ned_m.copy()

    # --- commands
    def _ack(self, link: str, msg: mavlink.MAVLink_message, command: int, result: int) -> Outgoing:
        return Outgoing(
            link, mavlink.MAVLink_command_ack_message(command, result, 0, 0, msg.get_srcSystem(), msg.get_srcComponent())
        )

    def _text(self, severity: int, text: str) -> Outgoing:
        return Outgoing(None, telemetry.statustext(severity, text))

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
        out: list[Outgoing] = []
        result = MAV_RESULT_UNSUPPORTED
        follow_up: list[Outgoing] = []
        if command == mavlink.MAV_CMD_COMPONENT_ARM_DISARM:
            result, out = self._cmd_arm(p, now_s)
        elif command == mavlink.MAV_CMD_DO_SET_MODE:
            result, out = self._cmd_set_mode(p, now_s)
        elif command == mavlink.MAV_CMD_NAV_TAKEOFF:
            result, out = self._cmd_takeoff(p, now_s)
        elif command == mavlink.MAV_CMD_NAV_LAND:
            result, out = self._cmd_land(now_s)
        elif command == mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH:
            result, out = self._request_mode(Px4Mode.AUTO_RTL, now_s) if self.armed else (MAV_RESULT_TEMPORARILY_REJECTED, [])
        elif command == mavlink.MAV_CMD_DO_REPOSITION:
            result, out = self._cmd_reposition(p, now_s, relative_alt)
        elif command == mavlink.MAV_CMD_DO_CHANGE_SPEED:
            result = self._cmd_change_speed(p)
        elif command == mavlink.MAV_CMD_SET_MESSAGE_INTERVAL:
            result = self._cmd_message_interval(link, p, now_s)
        elif command in (mavlink.MAV_CMD_REQUEST_MESSAGE, mavlink.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES, mavlink.MAV_CMD_GET_HOME_POSITION):
            result, follow_up = self._cmd_request_message(link, command, p, now_s)
        else:
            self.rejections["unsupported_command"] += 1
        if result not in (MAV_RESULT_ACCEPTED, MAV_RESULT_UNSUPPORTED):
            self.rejections[f"command_{command}_result_{result}"] += 1
        return out + [self._ack(link, msg, command, result)] + follow_up

    def _cmd_arm(self, p: list[float], now_s: float) -> tuple[int, list[Outgoing]]:
        if p[0] == 1.0:
            if self.armed:
                return MAV_RESULT_ACCEPTED, []
            reason = self.arming_denial(now_s)
            if reason is not None:
                return MAV_RESULT_TEMPORARILY_REJECTED, [self._text(SEVERITY_CRITICAL, f"Arming denied: {reason}")]
            self._arm(now_s)
            return MAV_RESULT_ACCEPTED, [self._text(SEVERITY_INFO, "Armed by external command")]
        if p[0] == 0.0:
            if not self.armed:
                return MAV_RESULT_ACCEPTED, []
            forced = int(p[1]) == FORCE_DISARM_MAGIC if math.isfinite(p[1]) else False
            if self.landed_state != LandedState.ON_GROUND and not self._on_ground() and not forced:
                return MAV_RESULT_TEMPORARILY_REJECTED, [self._text(SEVERITY_CRITICAL, "Disarming denied: not landed")]
            self._disarm("Disarmed by external command")
            return MAV_RESULT_ACCEPTED, []
        self.rejections["bad_arm_param"] += 1
        return MAV_RESULT_DENIED, []

    def _arm(self, now_s: float) -> None:
        self.armed = True
        self._arm_t_s = now_s
        self._took_off = False
        self._ground_since_s = now_s - LAND_DETECT_S if self._on_ground() else None
        if self.global_position_valid or not self.home_valid:
            self.home_ned_m = self.position_ned_m.copy()
            self.home_valid = self.global_position_valid
        self._hold_ned = self.position_ned_m.copy()

    def _disarm(self, reason: str) -> None:
        self.armed = False
        self.failsafe = False
        self._pending.append(self._text(SEVERITY_INFO, reason))
        if self.mode in (Px4Mode.AUTO_LAND, Px4Mode.AUTO_RTL, Px4Mode.AUTO_TAKEOFF):
            self._enter_mode(Px4Mode.AUTO_LOITER)

    def _cmd_set_mode(self, p: list[float], now_s: float) -> tuple[int, list[Outgoing]]:
        if not all(math.isfinite(x) for x in p[:3]) or not int(p[0]) & 1:
            self.rejections["bad_set_mode"] += 1
            return MAV_RESULT_DENIED, []
        mode = mode_from_numbers(int(p[1]), int(p[2]))
        if mode is None:
            self.rejections["unknown_mode"] += 1
            return MAV_RESULT_DENIED, []
        return self._request_mode(mode, now_s)

    def _cmd_takeoff(self, p: list[float], now_s: float) -> tuple[int, list[Outgoing]]:
        if not self.armed:
            return MAV_RESULT_TEMPORARILY_REJECTED, [self._text(SEVERITY_CRITICAL, "Takeoff denied: disarmed")]
        if self.mode == Px4Mode.AUTO_TAKEOFF:
            return MAV_RESULT_ACCEPTED, []
        if math.isfinite(p[6]):
            target_up_m = p[6] - (self.config.home.alt_m + self.config.pad_enu_m[2]) + float(self.home_ned_m[2])
        else:
            target_up_m = self.params["MIS_TAKEOFF_ALT"]
        if target_up_m <= 0.0:
            return MAV_RESULT_DENIED, [self._text(SEVERITY_CRITICAL, "Takeoff denied: altitude below home")]
        self._takeoff_down_m = float(self.home_ned_m[2]) - target_up_m
        self._enter_mode(Px4Mode.AUTO_TAKEOFF)
        self.failsafe = False
        return MAV_RESULT_ACCEPTED, [self._text(SEVERITY_INFO, f"Takeoff to {target_up_m:.1f} meters above home")]

    def _cmd_land(self, now_s: float) -> tuple[int, list[Outgoing]]:
        if not self.armed:
            return MAV_RESULT_TEMPORARILY_REJECTED, [self._text(SEVERITY_CRITICAL, "Land denied: disarmed")]
        if self.mode != Px4Mode.AUTO_LAND:
            self._enter_mode(Px4Mode.AUTO_LAND)
            self.failsafe = False
        return MAV_RESULT_ACCEPTED, []

    def _cmd_reposition(self, p: list[float], now_s: float, relative_alt: bool) -> tuple[int, list[Outgoing]]:
        if not self.armed or not self.global_position_valid:
            return MAV_RESULT_TEMPORARILY_REJECTED, [self._text(SEVERITY_CRITICAL, "Reposition denied: no global position")]
        target = self.position_ned_m.copy()
        if math.isfinite(p[4]) and math.isfinite(p[5]):
            if not (-90.0 <= p[4] <= 90.0 and -180.0 <= p[5] <= 180.0):
                return MAV_RESULT_DENIED, []
            enu = geodetic_to_enu(p[4], p[5], self.config.home.alt_m, self.config.home)
            target[:2] = mission_enu_to_local_ned(enu, self.config.pad_enu_m)[:2]
        if math.isfinite(p[6]):
            up_m = p[6] - float(self.home_ned_m[2]) if relative_alt else p[6] - self.config.home.alt_m - self.config.pad_enu_m[2]
            target[2] = -up_m
        if math.isfinite(p[0]) and p[0] > 0.0:
            self._cruise_speed_mps = min(p[0], self.params["MPC_XY_VEL_MAX"])
        self._enter_mode(Px4Mode.AUTO_LOITER)
        self._hold_ned = target
        self.failsafe = False
        return MAV_RESULT_ACCEPTED, []

    def _cmd_change_speed(self, p: list[float]) -> int:
        speed = p[1]
        if not math.isfinite(speed):
            return MAV_RESULT_DENIED
        if speed == -1.0:
            self._cruise_speed_mps = None
            return MAV_RESULT_ACCEPTED
        if speed <= 0.0:
            return MAV_RESULT_DENIED
        self._cruise_speed_mps = min(speed, self.params["MPC_XY_VEL_MAX"])
        return MAV_RESULT_ACCEPTED

    def stream_rates_hz(self, link: str) -> dict[str, float]:
        """Message name -> rate [Hz, simulated] this vehicle streams on ``link`` now (after SET_MESSAGE_INTERVAL)."""
        return {name: 1.0 / period for name, period in self._periods[link].items()}

    def _cmd_message_interval(self, link: str, p: list[float], now_s: float) -> int:
        if not (math.isfinite(p[0]) and math.isfinite(p[1])):
            return MAV_RESULT_DENIED
        name = telemetry.BUILDER_BY_ID.get(int(p[0]))
        if name is None or name == "AUTOPILOT_VERSION":
            return MAV_RESULT_DENIED
        interval_us = p[1]
        periods = self._periods[link]
        if interval_us == -1:
            periods.pop(name, None)
        elif interval_us == 0:
            default = stream_periods_s(self.config.stream_profile, link).get(name)
            if default is None:
                periods.pop(name, None)
            else:
                periods[name] = default
        elif interval_us > 0:
            periods[name] = max(interval_us * 1e-6, 0.001)
        else:
            return MAV_RESULT_DENIED
        if name in periods:
            # Keep the stream on its grid from boot rather than starting it now: streams whose rates divide each
            # other then fall due in the same tick and leave together, as in PX4's mavlink loop, which sends what
            # is due in one pass; a stream restarted at the command's time would wake the receiver separately.
            period = periods[name]
            due_s = self._stream_epoch_s + math.ceil((now_s - self._stream_epoch_s) / period - 1e-9) * period
            self._next_due[link][name] = due_s
            self._earliest_due[link] = min(self._earliest_due[link], due_s)
        return MAV_RESULT_ACCEPTED

    def _cmd_request_message(self, link: str, command: int, p: list[float], now_s: float) -> tuple[int, list[Outgoing]]:
        if command == mavlink.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES:
            name: str | None = "AUTOPILOT_VERSION"
        elif command == mavlink.MAV_CMD_GET_HOME_POSITION:
            name = "HOME_POSITION"
        else:
            name = telemetry.BUILDER_BY_ID.get(int(p[0])) if math.isfinite(p[0]) else None
        if name is None:
            return MAV_RESULT_UNSUPPORTED, []
        message = telemetry.BUILDERS[name](self, now_s)
        if message is None:
            return MAV_RESULT_TEMPORARILY_REJECTED, []
        return MAV_RESULT_ACCEPTED, [Outgoing(link, message)]

    # ------------------------------------------------------------------ faults (called by the fleet)
    def set_gps_available(self, available: bool, now_s: float) -> None:
        """Lose or regain the GPS (fault injection); only meaningful for a vehicle fitted with GPS."""
        if not self.config.has_gps or available == self.gps_available:
            return
        self.gps_available = available
        self._pending.append(self._text(SEVERITY_CRITICAL, "GPS regained" if available else "GPS lost: global position invalid"))

    def set_battery_remaining(self, fraction: float) -> None:
        """Drain (or refill) the battery to ``fraction`` of its capacity (fault injection)."""
        self.battery_remaining = float(min(1.0, max(0.0, fraction)))

    def kill(self) -> None:
        """Power loss: the vehicle stops talking and falls (fault injection)."""
        self.killed = True
        self.armed = False

    # ------------------------------------------------------------------ time
    def tick(self, now_s: float) -> list[Outgoing]:
        """Advance physics and timers to ``now_s`` and return due telemetry and event messages."""
        while self._t_s < now_s - 1e-9:
            dt = min(PHYSICS_STEP_S, now_s - self._t_s)
            self._step(dt)
        if self.killed:
            self._pending.clear()
            return []
        out, self._pending = self._pending, []
        built: dict[str, mavlink.MAVLink_message | None] = {}  # one message per stream and tick, shared by links
        horizon = now_s + self.stream_slack_s + 1e-9
        for link, periods in self._periods.items():
            if horizon < self._earliest_due[link]:
                continue
            due = self._next_due[link]
            for name, period in periods.items():
                next_t = due.get(name, now_s)
                if horizon < next_t:
                    continue
                if name not in built:
                    built[name] = telemetry.BUILDERS[name](self, now_s)
                message = built[name]
                if message is not None:
                    out.append(Outgoing(link, message))
                next_t += period
                if next_t <= now_s:
                    next_t = now_s + period
                due[name] = next_t
            self._earliest_due[link] = min((due.get(n, now_s) for n in periods), default=math.inf)
        return out

    def _on_ground(self) -> bool:
        return float(self.position_ned_m[2]) >= -GROUND_TOLERANCE_M

    def _limits(self) -> KinematicLimits:
        """PX4 velocity-controller limits from the parameters, rebuilt only when a parameter changed.

        The response time is the plant's (``VehicleConfig.response_time_s``), not a parameter: the same value the
        lockstep kinematics read, so both engines fly the same first-order velocity response.
        """
        if self._limits_version != self.params.version:
            self._limits_version = self.params.version
            self._limits_cache = KinematicLimits(
                max_xy_speed_mps=self.params["MPC_XY_VEL_MAX"],
                max_climb_speed_mps=self.params["MPC_Z_VEL_MAX_UP"],
                max_descent_speed_mps=max(self.params["MPC_Z_VEL_MAX_DN"], self.params["MPC_LAND_SPEED"]),
                max_xy_accel_mps2=self.params["MPC_ACC_HOR"],
                max_z_accel_mps2=self.params["MPC_ACC_UP_MAX"],
                response_time_s=self.config.response_time_s,
            )
        return self._limits_cache

    def _step(self, dt: float) -> None:
        t = self._t_s + dt
        if self.armed:
            command, yaw_target, yaw_rate = self._velocity_command(t)
            self._commanded_down_mps = float(command[2])
            wind = self._wind_ned if self._wind_ned is not None and not self._on_ground() else None
            new_body = step_kinematics(self.body, command, self._limits(), dt, wind_ned_mps=wind)
            self._update_yaw(yaw_target, yaw_rate, dt)
        else:
            new_body = self._fall(dt)
            self.yaw_rate_rad_s = 0.0
        if new_body is not self.body:
            self._accel_ned = (new_body.velocity_ned_mps - self.body.velocity_ned_mps) / dt
            self.body = new_body
        elif self._accel_ned is not _NO_ACCEL:
            self._accel_ned = _NO_ACCEL
        self._t_s = t
        self._drain_battery(dt)
        self._update_ground(t)
        self._check_timers(t)

    def _fall(self, dt: float) -> KinematicState:
        p, v = self.position_ned_m, self.velocity_ned_mps
        if self._on_ground() and v[2] <= 0.0:
            if p[2] == 0.0 and v[0] == 0.0 and v[1] == 0.0 and v[2] == 0.0:
                return self.body  # resting on the ground: nothing moves
            return KinematicState(position_ned_m=np.array([p[0], p[1], 0.0]), velocity_ned_mps=np.zeros(3))
        new_v = np.array([v[0] * math.exp(-dt), v[1] * math.exp(-dt), min(v[2] + GRAVITY_MPS2 * dt, 30.0)])
        new_p = p + new_v * dt
        if new_p[2] > 0.0:
            new_p[2] = 0.0
            new_v = np.zeros(3)
        return KinematicState(position_ned_m=new_p, velocity_ned_mps=new_v)

    def _goto(self, target: NDArray[np.float64], speed_xy: float, climb: float, descent: float) -> NDArray[np.float64]:
        """PX4's position loop: P on the position error, horizontal speed capped, vertical within climb/descent."""
        p = self.position_ned_m
        kxy = self.params["MPC_XY_P"]
        vx, vy = kxy * (float(target[0]) - float(p[0])), kxy * (float(target[1]) - float(p[1]))
        n = math.hypot(vx, vy)
        if n > speed_xy > 0.0:
            vx, vy = vx * speed_xy / n, vy * speed_xy / n
        vz = min(max(self.params["MPC_Z_P"] * (float(target[2]) - float(p[2])), -climb), descent)
        return np.array([vx, vy, vz])

    def _cruise(self) -> float:
        return self._cruise_speed_mps if self._cruise_speed_mps is not None else self.params["MPC_XY_CRUISE"]

    def _velocity_command(self, t: float) -> tuple[NDArray[np.float64], float, float]:
        """Velocity [m/s NED] the current mode asks for, plus a yaw target [rad] (NaN: none) and yaw rate."""
        up, down = self.params["MPC_Z_VEL_MAX_UP"], self.params["MPC_Z_VEL_MAX_DN"]
        mode = self.mode
        nan = math.nan
        if mode == Px4Mode.OFFBOARD:
            sp = self.offboard_setpoint
            if sp is None or not self.offboard_fresh(t):
                return self._goto(self._hold_ned, self._cruise(), up, down), nan, 0.0
            command = velocity_command_ned(
                sp, self.position_ned_m, self.velocity_ned_mps, self.params["MPC_XY_P"], self.params["MPC_Z_P"],
                self.config.response_time_s,
            )
            if self._on_ground() and command[2] > 0.0:
                command[2] = 0.0
            self._hold_ned = self.position_ned_m.copy()
            yaw_rate = sp.yaw_rate_rad_s if math.isfinite(sp.yaw_rate_rad_s) else 0.0
            return command, sp.yaw_rad, yaw_rate
        if mode == Px4Mode.AUTO_TAKEOFF:
            target = np.array([self._hold_ned[0], self._hold_ned[1], self._takeoff_down_m])
            tko = self.params["MPC_TKO_SPEED"]
            return self._goto(target, self._cruise(), tko, down), nan, 0.0
        if mode == Px4Mode.AUTO_LAND:
            command = self._goto(self._hold_ned, self._cruise(), up, down)
            command[2] = self.params["MPC_LAND_SPEED"]
            return command, nan, 0.0
        if mode == Px4Mode.AUTO_RTL:
            return self._rtl_command(up, down), nan, 0.0
        if mode in (Px4Mode.ALTCTL, Px4Mode.STABILIZED, Px4Mode.MANUAL):
            command = self._goto(self._hold_ned, self._cruise(), up, down)
            command[:2] = 0.0
            return command, nan, 0.0
        return self._goto(self._hold_ned, self._cruise(), up, down), nan, 0.0

    def _rtl_command(self, up: float, down: float) -> NDArray[np.float64]:
        p = self.position_ned_m
        return_down_m = min(float(p[2]), float(self.home_ned_m[2]) - self.params["RTL_RETURN_ALT"])
        if self._rtl_phase == "climb":
            if p[2] <= return_down_m + TAKEOFF_ACCEPT_M:
                self._rtl_phase = "return"
                self._hold_ned = np.array([self.home_ned_m[0], self.home_ned_m[1], p[2]])
            else:
                target = np.array([p[0], p[1], return_down_m])
                command = self._goto(target, 0.0, up, down)
                command[:2] = 0.0
                return command
        if self._rtl_phase == "return":
            if math.hypot(p[0] - self.home_ned_m[0], p[1] - self.home_ned_m[1]) < 0.5:
                self._rtl_phase = "land"
            else:
                return self._goto(self._hold_ned, self._cruise(), up, down)
        command = self._goto(np.array([self.home_ned_m[0], self.home_ned_m[1], p[2]]), self._cruise(), up, down)
        command[2] = self.params["MPC_LAND_SPEED"]
        return command

    def _update_yaw(self, yaw_target: float, yaw_rate: float, dt: float) -> None:
        max_rate = math.radians(self.params["MPC_YAWRAUTO_MAX"])
        if math.isfinite(yaw_target):
            error = (yaw_target - self.yaw_rad + math.pi) % (2 * math.pi) - math.pi
            rate = min(max(error / max(dt, 0.2), -max_rate), max_rate)
        else:
            rate = min(max(yaw_rate, -max_rate), max_rate)
        self.yaw_rate_rad_s = rate
        self.yaw_rad = (self.yaw_rad + rate * dt) % (2 * math.pi)

    def _update_ground(self, t: float) -> None:
        on_ground = self._on_ground()
        climbing = self.armed and self._commanded_down_mps < -0.1
        if self.armed and self.mode == Px4Mode.AUTO_TAKEOFF:
            climbing = True
        if on_ground and not climbing:
            if self._ground_since_s is None:
                self._ground_since_s = t
        else:
            self._ground_since_s = None
        if self.armed and float(self.position_ned_m[2]) < -0.5:
            self._took_off = True

    def _drain_battery(self, dt: float) -> None:
        if not self.armed:
            return
        floor = self.params["SIM_BAT_MIN_PCT"] / 100.0
        if self.battery_remaining > floor:
            self.battery_remaining = max(floor, self.battery_remaining - dt / self.params["SIM_BAT_DRAIN"])
        self.battery_consumed_mah += HOVER_CURRENT_A * dt / 3.6

    # ------------------------------------------------------------------ timers and failsafes
    def _check_timers(self, t: float) -> None:
        if self.killed:
            return
        if self.armed and self.mode == Px4Mode.AUTO_TAKEOFF and float(self.position_ned_m[2]) <= self._takeoff_down_m + TAKEOFF_ACCEPT_M:
            self._enter_mode(Px4Mode.AUTO_LOITER)
            self._hold_ned[2] = self._takeoff_down_m
        if self.armed and self.mode == Px4Mode.OFFBOARD and not self.offboard_fresh(t):
            self._failsafe_offboard_lost(t)
        if self.armed and not self.global_position_valid and MODE_TABLE[self.mode].needs_global_position:
            self._failsafe_to(Px4Mode.AUTO_LAND, "global position lost")
        self._check_datalink(t)
        self._check_battery()
        self._check_auto_disarm(t)

    def _failsafe_to(self, mode: Px4Mode, reason: str) -> None:
        if not mode_allowed(mode, self.local_position_valid, self.global_position_valid):
            mode = Px4Mode.AUTO_LAND
        self._enter_mode(mode)
        self.failsafe = True
        self._pending.append(self._text(SEVERITY_CRITICAL, f"Failsafe: {reason}, {mode.value}"))

    def _terminate(self, reason: str, disarm_only: bool) -> None:
        self._pending.append(self._text(SEVERITY_CRITICAL, f"Failsafe: {reason}, {'disarm' if disarm_only else 'terminate'}"))
        self.armed = False
        self.failsafe = not disarm_only

    def _apply_failsafe(self, action: FailsafeAction, reason: str) -> None:
        if action == TERMINATE or action == DISARM:
            self._terminate(reason, disarm_only=action == DISARM)
        else:
            self._failsafe_to(action, reason)

    def _failsafe_offboard_lost(self, t: float) -> None:
        self._apply_failsafe(OFFBOARD_LOSS_ACTIONS[self.params.get_int("COM_OBL_RC_ACT")], "offboard lost")

    def _check_datalink(self, t: float) -> None:
        action = DATALINK_LOSS_ACTIONS[self.params.get_int("NAV_DLL_ACT")]
        if action is None or not self.armed or self._last_gcs_heartbeat_s is None or self._datalink_lost:
            return
        if t - self._last_gcs_heartbeat_s <= self.params["COM_DL_LOSS_T"]:
            return
        self._datalink_lost = True
        self._apply_failsafe(action, "GCS connection lost")

    def _check_battery(self) -> None:
        remaining = self.battery_remaining
        if remaining == self._battery_checked:
            return
        self._battery_checked = remaining
        level = 0
        for i, name in enumerate(BATTERY_LEVELS, start=1):
            if remaining < self.params[name]:
                level = i
        if level <= self._battery_level_reported:
            return
        self._battery_level_reported = level
        label = {1: "low", 2: "critical", 3: "emergency"}[level]
        mode = battery_action(level, self.params.get_int("COM_LOW_BAT_ACT"))
        if mode is None or not self.armed or self._landed_for(0.0):
            severity = SEVERITY_CRITICAL if level > 1 else SEVERITY_WARNING
            self._pending.append(self._text(severity, f"Battery {label}: {remaining * 100:.0f}% remaining"))
            return
        self._failsafe_to(mode, f"battery {label}")

    def _landed_for(self, seconds: float) -> bool:
        return self._ground_since_s is not None and self._t_s - self._ground_since_s >= LAND_DETECT_S + seconds

    def _check_auto_disarm(self, t: float) -> None:
        if not self.armed:
            return
        if not self._took_off:
            prflt = self.params["COM_DISARM_PRFLT"]
            if prflt > 0.0 and self._on_ground() and t - self._arm_t_s > prflt and self.mode != Px4Mode.AUTO_TAKEOFF:
                self._disarm("Disarmed by auto preflight disarming")
            return
        land_s = self.params["COM_DISARM_LAND"]
        if land_s > 0.0 and self._landed_for(land_s):
            self._disarm("Disarmed by landing")
