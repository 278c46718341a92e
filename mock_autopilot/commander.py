"""PX4 commander reduced to the mock: arming checks, mode switches and what each needs, failsafes and the
auto-disarm timers, on a :class:`~mock_autopilot.vehicle_state.VehicleState`.

Each rule follows PX4's commander (src/modules/commander): the list, with the PX4 behaviour each one follows, is in
mock_autopilot/README.md. STATUSTEXTs the commander announces go to ``state.pending`` and leave with the next tick.
"""

from __future__ import annotations

import math

from pymavlink.dialects.v20 import common as mavlink

from comms.px4 import (
    MAV_MODE_FLAG_AUTO_ENABLED,
    MAV_MODE_FLAG_CUSTOM_MODE_ENABLED,
    MAV_MODE_FLAG_GUIDED_ENABLED,
    MAV_MODE_FLAG_MANUAL_INPUT_ENABLED,
    MAV_MODE_FLAG_STABILIZE_ENABLED,
    MODE_TABLE,
    PX4_MAIN_MODE_AUTO,
    MavResult,
    Px4Mode,
    mode_allowed,
    mode_from_numbers,
)
from mock_autopilot import telemetry
from mock_autopilot.battery import LEVEL_LABELS
from mock_autopilot.position_control import TAKEOFF_ACCEPT_M
from mock_autopilot.px4_failsafes import DATALINK_LOSS_ACTIONS, DISARM, OFFBOARD_LOSS_ACTIONS, TERMINATE
from mock_autopilot.px4_failsafes import FailsafeAction, battery_action
from mock_autopilot.vehicle_state import LAND_DETECT_S, Outgoing, RtlPhase, VehicleState

SEVERITY_CRITICAL = mavlink.MAV_SEVERITY_CRITICAL
SEVERITY_WARNING = mavlink.MAV_SEVERITY_WARNING
SEVERITY_INFO = mavlink.MAV_SEVERITY_INFO
_HOLD_HERE_MODES = (Px4Mode.AUTO_LOITER, Px4Mode.AUTO_READY, Px4Mode.POSCTL, Px4Mode.ALTCTL, Px4Mode.STABILIZED,
                    Px4Mode.MANUAL, Px4Mode.AUTO_TAKEOFF)
WIND_WARNING_PERIOD_S = 60.0
"""PX4 repeats the high-wind warning at most once a minute."""
_BACK_TO_HOLD_ON_DISARM = (Px4Mode.AUTO_LAND, Px4Mode.AUTO_RTL, Px4Mode.AUTO_TAKEOFF)


def text(severity: int, message: str) -> Outgoing:
    """A STATUSTEXT for every link."""
    return Outgoing(None, telemetry.statustext(severity, message))


def arming_denial(v: VehicleState, now_s: float) -> str | None:
    """Why PX4 would refuse to arm now, or None (also the PREARM_CHECK health bit)."""
    if v.killed:
        return "vehicle killed"
    if v.failsafe:
        return "failsafe active"
    if not v.local_position_valid:
        return "no local position"
    if v.config.has_gps and not v.gps_available and v.params.get_int("COM_ARM_WO_GPS") == 0:
        return "GPS fix required"
    if MODE_TABLE[v.mode].manual:
        return "manual control lost"
    if not mode_allowed(v.mode, v.local_position_valid, v.global_position_valid):
        return f"{v.mode.value} needs a global position"
    if v.mode == Px4Mode.OFFBOARD and not v.offboard_fresh(now_s):
        return "no offboard signal"
    wind_max = v.params["COM_WIND_MAX"]
    if wind_max > 0.0 and horizontal_wind_mps(v) > wind_max:
        return f"Wind speed is above limit ({horizontal_wind_mps(v):.1f} m/s)"
    if v.battery.remaining < v.params["BAT_EMERGEN_THR"]:
        return "battery too low"
    return None


def request_mode(v: VehicleState, mode: Px4Mode, now_s: float) -> tuple[MavResult, list[Outgoing]]:
    """A mode switch asked for by a client (DO_SET_MODE, SET_MODE, RTL): accepted, or refused as PX4 refuses it."""
    if mode == v.mode:
        return MavResult.ACCEPTED, []
    if not mode_allowed(mode, v.local_position_valid, v.global_position_valid):
        return MavResult.TEMPORARILY_REJECTED, [text(SEVERITY_CRITICAL, f"Switching to {mode.value} is currently not possible")]
    if mode == Px4Mode.AUTO_MISSION:
        return MavResult.TEMPORARILY_REJECTED, [text(SEVERITY_CRITICAL, "Mission rejected: no mission")]
    if mode == Px4Mode.OFFBOARD and not v.offboard_fresh(now_s):
        return MavResult.TEMPORARILY_REJECTED, [text(SEVERITY_CRITICAL, "Switching to Offboard is currently not possible")]
    enter_mode(v, mode)
    v.failsafe = False
    return MavResult.ACCEPTED, []


def set_mode(v: VehicleState, base_mode: int, main_mode: int, sub_mode: int, now_s: float) -> tuple[MavResult, list[Outgoing]]:
    """DO_SET_MODE / SET_MODE as PX4 commander reads them: with CUSTOM_MODE_ENABLED the PX4 main/sub mode (AUTO
    without a sub mode is MISSION; an AUTO sub mode PX4 does not know is refused), else the standard base-mode flags
    (AUTO -> MISSION, MANUAL_INPUT with GUIDED -> POSCTL, with STABILIZE -> STABILIZED, alone -> MANUAL). A request
    naming no mode at all changes nothing and is accepted, as in PX4."""
    if base_mode & MAV_MODE_FLAG_CUSTOM_MODE_ENABLED:
        if main_mode == PX4_MAIN_MODE_AUTO and sub_mode == 0:
            sub_mode = MODE_TABLE[Px4Mode.AUTO_MISSION].sub_mode
        mode = mode_from_numbers(main_mode, sub_mode)
        if mode is None and main_mode == PX4_MAIN_MODE_AUTO:
            v.rejections["unknown_mode"] += 1
            return MavResult.TEMPORARILY_REJECTED, [text(SEVERITY_CRITICAL, "Unsupported auto mode")]
    else:
        mode = _mode_from_base_flags(base_mode)
    if mode is None:
        v.rejections["unknown_mode"] += 1
        return MavResult.ACCEPTED, []
    return request_mode(v, mode, now_s)


def _mode_from_base_flags(base_mode: int) -> Px4Mode | None:
    if base_mode & MAV_MODE_FLAG_AUTO_ENABLED:
        return Px4Mode.AUTO_MISSION
    if not base_mode & MAV_MODE_FLAG_MANUAL_INPUT_ENABLED:
        return None
    if base_mode & MAV_MODE_FLAG_GUIDED_ENABLED:
        return Px4Mode.POSCTL
    return Px4Mode.STABILIZED if base_mode & MAV_MODE_FLAG_STABILIZE_ENABLED else Px4Mode.MANUAL


def enter_mode(v: VehicleState, mode: Px4Mode) -> None:
    """Switch to ``mode``: the hold modes hold where the vehicle is, RTL starts with its climb."""
    v.mode = mode
    if mode in _HOLD_HERE_MODES:
        v.hold_ned = v.position_ned_m.copy()
    if mode == Px4Mode.AUTO_RTL:
        v.rtl_phase = RtlPhase.CLIMB


def arm(v: VehicleState, now_s: float) -> None:
    """Arm: home is set here (where a global position exists), and the vehicle holds where it stands."""
    v.armed = True
    v.arm_t_s = now_s
    v.took_off = False
    v.ground_since_s = now_s - LAND_DETECT_S if v.on_ground() else None
    if v.global_position_valid or not v.home_valid:
        v.home_ned_m = v.position_ned_m.copy()
        v.home_valid = v.global_position_valid
    v.hold_ned = v.position_ned_m.copy()


def disarm(v: VehicleState, reason: str) -> None:
    """Disarm, announce why; after an automatic flight the mode returns to Hold, as PX4 commander does."""
    v.armed = False
    v.failsafe = False
    v.pending.append(text(SEVERITY_INFO, reason))
    if v.mode in _BACK_TO_HOLD_ON_DISARM:
        enter_mode(v, Px4Mode.AUTO_LOITER)


def failsafe_to(v: VehicleState, mode: Px4Mode, reason: str) -> None:
    """Enter a failsafe mode (Land where the mode is not possible), flag it, announce it."""
    if not mode_allowed(mode, v.local_position_valid, v.global_position_valid):
        mode = Px4Mode.AUTO_LAND
    enter_mode(v, mode)
    v.failsafe = True
    v.pending.append(text(SEVERITY_CRITICAL, f"Failsafe: {reason}, {mode.value}"))


def apply_failsafe(v: VehicleState, action: FailsafeAction, reason: str) -> None:
    """A failsafe action: a mode, or the motors off (terminate keeps the failsafe flagged, disarm does not)."""
    if action == TERMINATE or action == DISARM:
        disarm_only = action == DISARM
        v.pending.append(text(SEVERITY_CRITICAL, f"Failsafe: {reason}, {'disarm' if disarm_only else 'terminate'}"))
        v.armed = False
        v.failsafe = not disarm_only
    else:
        failsafe_to(v, action, reason)


def check_timers(v: VehicleState, t_s: float) -> None:
    """Commander's periodic checks after each physics step: takeoff done, offboard and GPS loss, data link,
    battery, auto-disarm."""
    if v.killed:
        return
    if v.armed and v.mode == Px4Mode.AUTO_TAKEOFF and float(v.position_ned_m[2]) <= v.takeoff_down_m + TAKEOFF_ACCEPT_M:
        enter_mode(v, Px4Mode.AUTO_LOITER)
        v.hold_ned[2] = v.takeoff_down_m
    if v.armed and v.mode == Px4Mode.OFFBOARD and not v.offboard_fresh(t_s):
        apply_failsafe(v, OFFBOARD_LOSS_ACTIONS[v.params.get_int("COM_OBL_RC_ACT")], "offboard lost")
    if v.armed and not v.global_position_valid and MODE_TABLE[v.mode].needs_global_position:
        failsafe_to(v, Px4Mode.AUTO_LAND, "global position lost")
    _check_datalink(v, t_s)
    _check_battery(v)
    _check_wind(v, t_s)
    _check_auto_disarm(v, t_s)


def horizontal_wind_mps(v: VehicleState) -> float:
    """Speed [m/s] of the estimator's horizontal wind."""
    wind = v.wind_estimate_ned_mps
    return float(math.hypot(wind[0], wind[1]))


def _check_wind(v: VehicleState, t_s: float) -> None:
    """PX4's wind check: above COM_WIND_MAX a Return failsafe (once, until the wind drops or the vehicle
    disarms), else above COM_WIND_WARN a warning at most once a minute, not while returning or landing."""
    warn, limit = v.params["COM_WIND_WARN"], v.params["COM_WIND_MAX"]
    if (warn <= 0.0 and limit <= 0.0) or v.weather is None:
        return
    speed = horizontal_wind_mps(v)
    exceeded = limit > 0.0 and speed > limit
    if not exceeded or not v.armed:
        v.wind_limit_latched = False
    if exceeded:
        if v.armed and not v.on_ground() and not v.wind_limit_latched:
            v.wind_limit_latched = True
            failsafe_to(v, Px4Mode.AUTO_RTL, f"wind speed above limit ({speed:.1f} m/s)")
        return
    quiet = v.wind_warning_t_s is not None and t_s - v.wind_warning_t_s <= WIND_WARNING_PERIOD_S
    if warn > 0.0 and speed > warn and not quiet and v.mode not in (Px4Mode.AUTO_RTL, Px4Mode.AUTO_LAND):
        v.pending.append(text(SEVERITY_WARNING, f"High wind speed detected ({speed:.1f} m/s), landing advised"))
        v.wind_warning_t_s = t_s


def _check_datalink(v: VehicleState, t_s: float) -> None:
    action = DATALINK_LOSS_ACTIONS[v.params.get_int("NAV_DLL_ACT")]
    if action is None or not v.armed or v.last_gcs_heartbeat_s is None or v.datalink_lost:
        return
    if t_s - v.last_gcs_heartbeat_s <= v.params["COM_DL_LOSS_T"]:
        return
    v.datalink_lost = True
    apply_failsafe(v, action, "GCS connection lost")


def _check_battery(v: VehicleState) -> None:
    level = v.battery.new_level(v.params)
    if level is None:
        return
    label = LEVEL_LABELS[level]
    mode = battery_action(level, v.params.get_int("COM_LOW_BAT_ACT"))
    if mode is None or not v.armed or v.landed_for(0.0):
        severity = SEVERITY_CRITICAL if level > 1 else SEVERITY_WARNING
        v.pending.append(text(severity, f"Battery {label}: {v.battery.remaining * 100:.0f}% remaining"))
        return
    failsafe_to(v, mode, f"battery {label}")


def _check_auto_disarm(v: VehicleState, t_s: float) -> None:
    if not v.armed:
        return
    if not v.took_off:
        prflt = v.params["COM_DISARM_PRFLT"]
        if prflt > 0.0 and v.on_ground() and t_s - v.arm_t_s > prflt and v.mode != Px4Mode.AUTO_TAKEOFF:
            disarm(v, "Disarmed by auto preflight disarming")
        return
    land_s = v.params["COM_DISARM_LAND"]
    if land_s > 0.0 and v.landed_for(land_s):
        disarm(v, "Disarmed by landing")
