"""The MAV_CMDs a PX4 multicopter answers, as a table from command id to handler.

Each handler takes the vehicle state, the link the command came on, the command id, its seven parameters (params
5-6 as degrees for COMMAND_INT), the simulated time and whether the altitude is relative to home, and returns the
COMMAND_ACK's result with the messages to send before the ACK (STATUSTEXT) and after it (a requested message).
A command missing from :data:`COMMAND_HANDLERS` is answered UNSUPPORTED, as PX4's commander does.
"""

from __future__ import annotations

import math
from typing import Callable, NamedTuple

from pymavlink.dialects.v20 import common as mavlink

from comms.frames import geodetic_to_enu, mission_enu_to_local_ned
from comms.px4 import LandedState, MavResult, Px4Mode
from mock_autopilot import commander, telemetry
from mock_autopilot.commander import SEVERITY_CRITICAL, SEVERITY_INFO, text
from mock_autopilot.vehicle_snapshot import take_snapshot
from mock_autopilot.vehicle_state import Outgoing, VehicleState

FORCE_DISARM_MAGIC = 21196


class CommandReply(NamedTuple):
    """A command's result, the messages sent before its COMMAND_ACK (STATUSTEXT) and after it (the message a
    REQUEST_MESSAGE asked for)."""

    result: MavResult
    before: list[Outgoing]
    after: list[Outgoing]


def _reply(result: MavResult, before: list[Outgoing] | None = None) -> CommandReply:
    return CommandReply(result, before or [], [])


def _refuse(message: str) -> CommandReply:
    return _reply(MavResult.TEMPORARILY_REJECTED, [text(SEVERITY_CRITICAL, message)])


def _rounded(value: float) -> int | None:
    """PX4 reads integer-valued params with lroundf; None for NaN and infinities."""
    return int(round(value)) if math.isfinite(value) else None


def arm_disarm(v: VehicleState, link: str, command: int, p: list[float], now_s: float, relative_alt: bool) -> CommandReply:
    action = _rounded(p[0])
    if action == 1:
        if v.armed:
            return _reply(MavResult.ACCEPTED)
        reason = commander.arming_denial(v, now_s)
        if reason is not None:
            return _refuse(f"Arming denied: {reason}")
        commander.arm(v, now_s)
        return _reply(MavResult.ACCEPTED, [text(SEVERITY_INFO, "Armed by external command")])
    if action == 0:
        if not v.armed:
            return _reply(MavResult.ACCEPTED)
        forced = _rounded(p[1]) == FORCE_DISARM_MAGIC
        if v.landed_state != LandedState.ON_GROUND and not v.on_ground() and not forced:
            return _refuse("Disarming denied: not landed")
        commander.disarm(v, "Disarmed by external command")
        return _reply(MavResult.ACCEPTED)
    v.rejections["bad_arm_param"] += 1
    return _reply(MavResult.UNSUPPORTED, [text(SEVERITY_CRITICAL, f"Unsupported ARM_DISARM param: {p[0]:.3f}")])


def set_mode(v: VehicleState, link: str, command: int, p: list[float], now_s: float, relative_alt: bool) -> CommandReply:
    if not all(math.isfinite(x) for x in p[:3]):
        v.rejections["bad_set_mode"] += 1
        return _reply(MavResult.DENIED)
    return _reply(*commander.set_mode(v, int(p[0]) & 0xFF, int(p[1]) & 0xFF, int(p[2]) & 0xFF, now_s))


def takeoff(v: VehicleState, link: str, command: int, p: list[float], now_s: float, relative_alt: bool) -> CommandReply:
    if v.mode == Px4Mode.AUTO_TAKEOFF:
        return _reply(MavResult.ACCEPTED)
    if math.isfinite(p[6]):
        target_up_m = p[6] - (v.config.home.alt_m + v.config.pad_enu_m[2]) + float(v.home_ned_m[2])
    else:
        target_up_m = v.params["MIS_TAKEOFF_ALT"]
    if target_up_m <= 0.0:
        return _reply(MavResult.DENIED, [text(SEVERITY_CRITICAL, "Takeoff denied: altitude below home")])
    result, texts = commander.request_mode(v, Px4Mode.AUTO_TAKEOFF, now_s)
    if result != MavResult.ACCEPTED:
        return _reply(result, texts)
    v.takeoff_down_m = float(v.home_ned_m[2]) - target_up_m
    return _reply(MavResult.ACCEPTED, [text(SEVERITY_INFO, f"Takeoff to {target_up_m:.1f} meters above home")])


def land(v: VehicleState, link: str, command: int, p: list[float], now_s: float, relative_alt: bool) -> CommandReply:
    result, texts = commander.request_mode(v, Px4Mode.AUTO_LAND, now_s)
    if result == MavResult.ACCEPTED:
        texts.append(text(SEVERITY_INFO, "Landing at current position"))
    return _reply(result, texts)


def return_to_launch(v: VehicleState, link: str, command: int, p: list[float], now_s: float, relative_alt: bool) -> CommandReply:
    result, texts = commander.request_mode(v, Px4Mode.AUTO_RTL, now_s)
    if result == MavResult.ACCEPTED:
        texts.append(text(SEVERITY_INFO, "Returning to launch"))
    return _reply(result, texts)


def reposition(v: VehicleState, link: str, command: int, p: list[float], now_s: float, relative_alt: bool) -> CommandReply:
    if _rounded(p[1]) != mavlink.MAV_DO_REPOSITION_FLAGS_CHANGE_MODE:
        return _reply(MavResult.UNSUPPORTED)  # PX4 only repositions when asked to switch to Hold, with no other flag
    if not v.armed or not v.global_position_valid:
        return _refuse("Reposition denied: no global position")
    target = v.position_ned_m.copy()
    if math.isfinite(p[4]) and math.isfinite(p[5]):
        if not (-90.0 <= p[4] <= 90.0 and -180.0 <= p[5] <= 180.0):
            return _reply(MavResult.DENIED)
        enu = geodetic_to_enu(p[4], p[5], v.config.home.alt_m, v.config.home)
        target[:2] = mission_enu_to_local_ned(enu, v.config.pad_enu_m)[:2]
    if math.isfinite(p[6]):
        up_m = p[6] - float(v.home_ned_m[2]) if relative_alt else p[6] - v.config.home.alt_m - v.config.pad_enu_m[2]
        target[2] = -up_m
    if math.isfinite(p[0]) and p[0] > 0.0:
        v.cruise_speed_mps = min(p[0], v.params["MPC_XY_VEL_MAX"])
    commander.enter_mode(v, Px4Mode.AUTO_LOITER)
    v.hold_ned = target
    v.failsafe = False
    return _reply(MavResult.ACCEPTED)


def change_speed(v: VehicleState, link: str, command: int, p: list[float], now_s: float, relative_alt: bool) -> CommandReply:
    speed = p[1]
    if not math.isfinite(speed):
        return _reply(MavResult.DENIED)
    if speed == -1.0:
        v.cruise_speed_mps = None
        return _reply(MavResult.ACCEPTED)
    if speed <= 0.0:
        return _reply(MavResult.DENIED)
    v.cruise_speed_mps = min(speed, v.params["MPC_XY_VEL_MAX"])
    return _reply(MavResult.ACCEPTED)


def message_interval(v: VehicleState, link: str, command: int, p: list[float], now_s: float, relative_alt: bool) -> CommandReply:
    if not (math.isfinite(p[0]) and math.isfinite(p[1])):
        return _reply(MavResult.DENIED)
    name = telemetry.BUILDER_BY_ID.get(int(p[0]))
    if name is None or name == "AUTOPILOT_VERSION":
        return _reply(MavResult.DENIED)
    ok = v.streams.set_interval(link, name, p[1], now_s)
    return _reply(MavResult.ACCEPTED if ok else MavResult.DENIED)


_REQUESTED_BY_COMMAND = {
    mavlink.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES: "AUTOPILOT_VERSION",
    mavlink.MAV_CMD_GET_HOME_POSITION: "HOME_POSITION",
}


def request_message(v: VehicleState, link: str, command: int, p: list[float], now_s: float, relative_alt: bool) -> CommandReply:
    """Send the message asked for once, after the ACK. A message the vehicle has nothing to fill with (HOME_POSITION
    before home is set, as on a vehicle without GPS) is DENIED, as PX4's receiver answers when the stream sends
    nothing."""
    name = _REQUESTED_BY_COMMAND.get(command)
    if name is None:
        name = telemetry.BUILDER_BY_ID.get(int(p[0])) if math.isfinite(p[0]) else None
    if name is None:
        return _reply(MavResult.UNSUPPORTED)
    message = telemetry.BUILDERS[name](take_snapshot(v, now_s))
    if message is None:
        return _reply(MavResult.DENIED)
    return CommandReply(MavResult.ACCEPTED, [], [Outgoing(link, message)])


CommandHandler = Callable[[VehicleState, str, int, list[float], float, bool], CommandReply]

COMMAND_HANDLERS: dict[int, CommandHandler] = {
    mavlink.MAV_CMD_COMPONENT_ARM_DISARM: arm_disarm,
    mavlink.MAV_CMD_DO_SET_MODE: set_mode,
    mavlink.MAV_CMD_NAV_TAKEOFF: takeoff,
    mavlink.MAV_CMD_NAV_LAND: land,
    mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH: return_to_launch,
    mavlink.MAV_CMD_DO_REPOSITION: reposition,
    mavlink.MAV_CMD_DO_CHANGE_SPEED: change_speed,
    mavlink.MAV_CMD_SET_MESSAGE_INTERVAL: message_interval,
    mavlink.MAV_CMD_REQUEST_MESSAGE: request_message,
    mavlink.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES: request_message,
    mavlink.MAV_CMD_GET_HOME_POSITION: request_message,
}
