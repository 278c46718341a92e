"""PX4 flight modes as data: the custom_mode encoding, heartbeat base_mode flags and what each mode needs.

PX4 packs its mode into HEARTBEAT.custom_mode as ``(sub_mode << 24) | (main_mode << 16)`` (PX4_INTERFACE.md).
The base_mode flags follow PX4's heartbeat stream: CUSTOM_MODE_ENABLED always, SAFETY_ARMED when armed, and
MANUAL_INPUT / STABILIZE / GUIDED / AUTO as PX4 sets them per navigation state. The position requirements
mirror PX4 commander's mode requirements, with one documented simplification: Hold (AUTO.LOITER), takeoff and
land fly on local position alone (newer PX4 allows this), while RTL and MISSION need a global position.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

MAV_MODE_FLAG_CUSTOM_MODE_ENABLED = 1
MAV_MODE_FLAG_AUTO_ENABLED = 4
MAV_MODE_FLAG_GUIDED_ENABLED = 8
MAV_MODE_FLAG_STABILIZE_ENABLED = 16
MAV_MODE_FLAG_MANUAL_INPUT_ENABLED = 64
MAV_MODE_FLAG_SAFETY_ARMED = 128

_AUTO_FLAGS = MAV_MODE_FLAG_AUTO_ENABLED | MAV_MODE_FLAG_STABILIZE_ENABLED | MAV_MODE_FLAG_GUIDED_ENABLED


class Px4Mode(Enum):
    """PX4 navigation modes the mock flies; the value is the name QGroundControl shows."""

    MANUAL = "MANUAL"
    ALTCTL = "ALTCTL"
    POSCTL = "POSCTL"
    OFFBOARD = "OFFBOARD"
    STABILIZED = "STABILIZED"
    AUTO_READY = "AUTO.READY"
    AUTO_TAKEOFF = "AUTO.TAKEOFF"
    AUTO_LOITER = "AUTO.LOITER"
    AUTO_MISSION = "AUTO.MISSION"
    AUTO_RTL = "AUTO.RTL"
    AUTO_LAND = "AUTO.LAND"


@dataclass(frozen=True)
class ModeSpec:
    """One row of the mode table: PX4 main/sub mode numbers, heartbeat flags, and requirements."""

    main_mode: int
    sub_mode: int
    base_flags: int
    needs_local_position: bool
    needs_global_position: bool
    manual: bool


MODE_TABLE: dict[Px4Mode, ModeSpec] = {
    Px4Mode.MANUAL: ModeSpec(1, 0, MAV_MODE_FLAG_MANUAL_INPUT_ENABLED | MAV_MODE_FLAG_STABILIZE_ENABLED, False, False, True),
    Px4Mode.ALTCTL: ModeSpec(2, 0, MAV_MODE_FLAG_MANUAL_INPUT_ENABLED | MAV_MODE_FLAG_STABILIZE_ENABLED, False, False, True),
    Px4Mode.POSCTL: ModeSpec(
        3, 0, MAV_MODE_FLAG_MANUAL_INPUT_ENABLED | MAV_MODE_FLAG_STABILIZE_ENABLED | MAV_MODE_FLAG_GUIDED_ENABLED, True, False, True
    ),
    Px4Mode.AUTO_READY: ModeSpec(4, 1, _AUTO_FLAGS, True, False, False),
    Px4Mode.AUTO_TAKEOFF: ModeSpec(4, 2, _AUTO_FLAGS, True, False, False),
    Px4Mode.AUTO_LOITER: ModeSpec(4, 3, _AUTO_FLAGS, True, False, False),
    Px4Mode.AUTO_MISSION: ModeSpec(4, 4, _AUTO_FLAGS, True, True, False),
    Px4Mode.AUTO_RTL: ModeSpec(4, 5, _AUTO_FLAGS, True, True, False),
    Px4Mode.AUTO_LAND: ModeSpec(4, 6, _AUTO_FLAGS, True, False, False),
    Px4Mode.OFFBOARD: ModeSpec(6, 0, _AUTO_FLAGS, True, False, False),
    Px4Mode.STABILIZED: ModeSpec(7, 0, MAV_MODE_FLAG_MANUAL_INPUT_ENABLED | MAV_MODE_FLAG_STABILIZE_ENABLED, False, False, True),
}

_BY_NUMBERS: dict[tuple[int, int], Px4Mode] = {(s.main_mode, s.sub_mode): m for m, s in MODE_TABLE.items()}


def custom_mode(mode: Px4Mode) -> int:
    """HEARTBEAT.custom_mode of a PX4 mode: ``(sub << 24) | (main << 16)``."""
    spec = MODE_TABLE[mode]
    return (spec.sub_mode << 24) | (spec.main_mode << 16)


def mode_from_custom_mode(value: int) -> Px4Mode | None:
    """Inverse of :func:`custom_mode`; None for numbers PX4 does not define (or bits outside main/sub)."""
    if value < 0 or value & 0xFFFF:
        return None
    return mode_from_numbers((value >> 16) & 0xFF, (value >> 24) & 0xFF)


def mode_from_numbers(main_mode: int, sub_mode: int) -> Px4Mode | None:
    """Mode from DO_SET_MODE's param2/param3. A main mode other than AUTO ignores the sub mode (as PX4 does)."""
    if main_mode != 4:
        sub_mode = 0
    return _BY_NUMBERS.get((main_mode, sub_mode))


def base_mode(mode: Px4Mode, armed: bool) -> int:
    """HEARTBEAT.base_mode as PX4 fills it for a multicopter."""
    flags = MAV_MODE_FLAG_CUSTOM_MODE_ENABLED | MODE_TABLE[mode].base_flags
    return flags | (MAV_MODE_FLAG_SAFETY_ARMED if armed else 0)


def mode_allowed(mode: Px4Mode, local_position_valid: bool, global_position_valid: bool) -> bool:
    """Whether PX4 would accept a switch to ``mode`` with the given position estimates."""
    spec = MODE_TABLE[mode]
    if spec.needs_global_position and not global_position_valid:
        return False
    return not (spec.needs_local_position and not local_position_valid)
