"""What every package knows about PX4 over MAVLink, as data: flight modes and their names, heartbeat flags,
landed states, command results, and how a datagram splits into MAVLink frames.

PX4 packs its mode into HEARTBEAT.custom_mode as ``(sub_mode << 24) | (main_mode << 16)`` (PX4's
``px4_custom_mode.h``); the same numbers go into DO_SET_MODE's param2/param3. QGroundControl shows the
commander's names (AUTO.LOITER), MAVSDK its own (HOLD): both are columns of one table here, the names taken from
:mod:`comms.px4_mode_names` (and re-exported), which a MAVSDK agent imports alone so that it never loads pymavlink.
The flag, result and landed-state numbers are pymavlink's, so no package writes a MAVLink number by hand.

The requirement columns follow PX4 commander's mode requirements, with one simplification: Hold, takeoff and land
fly on local position alone (newer PX4 allows this), while RTL and MISSION need a global position.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

from pymavlink.dialects.v20 import common as mavlink

from comms.px4_mode_names import MAVSDK_MODE_NAMES, MAVSDK_OFFBOARD  # noqa: F401 (named here too)
from comms.px4_mode_names import MAVSDK_NAMES, Px4Mode

MAV_MODE_FLAG_CUSTOM_MODE_ENABLED: int = mavlink.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
MAV_MODE_FLAG_AUTO_ENABLED: int = mavlink.MAV_MODE_FLAG_AUTO_ENABLED
MAV_MODE_FLAG_GUIDED_ENABLED: int = mavlink.MAV_MODE_FLAG_GUIDED_ENABLED
MAV_MODE_FLAG_STABILIZE_ENABLED: int = mavlink.MAV_MODE_FLAG_STABILIZE_ENABLED
MAV_MODE_FLAG_MANUAL_INPUT_ENABLED: int = mavlink.MAV_MODE_FLAG_MANUAL_INPUT_ENABLED
MAV_MODE_FLAG_SAFETY_ARMED: int = mavlink.MAV_MODE_FLAG_SAFETY_ARMED

PX4_MAIN_MODE_AUTO = 4
"""The main mode whose sub modes (takeoff, loiter, mission, RTL, land ...) are the automatic flight modes."""


class MavResult(IntEnum):
    """MAV_RESULT of a COMMAND_ACK (pymavlink's values)."""

    ACCEPTED = mavlink.MAV_RESULT_ACCEPTED
    TEMPORARILY_REJECTED = mavlink.MAV_RESULT_TEMPORARILY_REJECTED
    DENIED = mavlink.MAV_RESULT_DENIED
    UNSUPPORTED = mavlink.MAV_RESULT_UNSUPPORTED
    FAILED = mavlink.MAV_RESULT_FAILED
    IN_PROGRESS = mavlink.MAV_RESULT_IN_PROGRESS


class LandedState(IntEnum):
    """MAV_LANDED_STATE of EXTENDED_SYS_STATE (pymavlink's values); the name is what a ground station shows."""

    UNDEFINED = mavlink.MAV_LANDED_STATE_UNDEFINED
    ON_GROUND = mavlink.MAV_LANDED_STATE_ON_GROUND
    IN_AIR = mavlink.MAV_LANDED_STATE_IN_AIR
    TAKEOFF = mavlink.MAV_LANDED_STATE_TAKEOFF
    LANDING = mavlink.MAV_LANDED_STATE_LANDING

    @property
    def airborne(self) -> bool:
        """In the air, taking off or landing (MAVSDK's ``in_air``)."""
        return self in (LandedState.IN_AIR, LandedState.TAKEOFF, LandedState.LANDING)


LANDED_STATE_LABELS: dict[LandedState, str] = {
    LandedState.UNDEFINED: "unknown",
    LandedState.ON_GROUND: "on ground",
    LandedState.IN_AIR: "in air",
    LandedState.TAKEOFF: "takeoff",
    LandedState.LANDING: "landing",
}


def landed_state_name(value: int) -> str:
    """EXTENDED_SYS_STATE.landed_state as a ground station shows it; the number itself when MAVLink has none."""
    try:
        return LANDED_STATE_LABELS[LandedState(value)]
    except ValueError:
        return str(value)


@dataclass(frozen=True)
class ModeSpec:
    """One row of the mode table: PX4's main/sub numbers, the name MAVSDK shows, heartbeat flags, requirements."""

    main_mode: int
    sub_mode: int
    mavsdk_name: str
    base_flags: int
    needs_local_position: bool
    needs_global_position: bool
    manual: bool


_MANUAL = MAV_MODE_FLAG_MANUAL_INPUT_ENABLED | MAV_MODE_FLAG_STABILIZE_ENABLED
_AUTO = MAV_MODE_FLAG_AUTO_ENABLED | MAV_MODE_FLAG_STABILIZE_ENABLED | MAV_MODE_FLAG_GUIDED_ENABLED

MODE_TABLE: dict[Px4Mode, ModeSpec] = {
    Px4Mode.MANUAL: ModeSpec(1, 0, MAVSDK_NAMES[Px4Mode.MANUAL], _MANUAL, False, False, True),
    Px4Mode.ALTCTL: ModeSpec(2, 0, MAVSDK_NAMES[Px4Mode.ALTCTL], _MANUAL, False, False, True),
    Px4Mode.POSCTL: ModeSpec(3, 0, MAVSDK_NAMES[Px4Mode.POSCTL], _MANUAL | MAV_MODE_FLAG_GUIDED_ENABLED,
                             True, False, True),
    Px4Mode.AUTO_READY: ModeSpec(4, 1, MAVSDK_NAMES[Px4Mode.AUTO_READY], _AUTO, True, False, False),
    Px4Mode.AUTO_TAKEOFF: ModeSpec(4, 2, MAVSDK_NAMES[Px4Mode.AUTO_TAKEOFF], _AUTO, True, False, False),
    Px4Mode.AUTO_LOITER: ModeSpec(4, 3, MAVSDK_NAMES[Px4Mode.AUTO_LOITER], _AUTO, True, False, False),
    Px4Mode.AUTO_MISSION: ModeSpec(4, 4, MAVSDK_NAMES[Px4Mode.AUTO_MISSION], _AUTO, True, True, False),
    Px4Mode.AUTO_RTL: ModeSpec(4, 5, MAVSDK_NAMES[Px4Mode.AUTO_RTL], _AUTO, True, True, False),
    Px4Mode.AUTO_LAND: ModeSpec(4, 6, MAVSDK_NAMES[Px4Mode.AUTO_LAND], _AUTO, True, False, False),
    Px4Mode.OFFBOARD: ModeSpec(6, 0, MAVSDK_NAMES[Px4Mode.OFFBOARD], _AUTO, True, False, False),
    Px4Mode.STABILIZED: ModeSpec(7, 0, MAVSDK_NAMES[Px4Mode.STABILIZED], _MANUAL, False, False, True),
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
    if main_mode != PX4_MAIN_MODE_AUTO:
        sub_mode = 0
    return _BY_NUMBERS.get((main_mode, sub_mode))


def mode_name(value: int) -> str:
    """HEARTBEAT.custom_mode as QGroundControl names it; ``MODE<main>`` / ``AUTO.<sub>`` for numbers without a name."""
    mode = mode_from_numbers((value >> 16) & 0xFF, (value >> 24) & 0xFF)
    if mode is not None:
        return mode.value
    main_mode = (value >> 16) & 0xFF
    return f"AUTO.{(value >> 24) & 0xFF}" if main_mode == PX4_MAIN_MODE_AUTO else f"MODE{main_mode}"


def mavsdk_mode_name(value: int) -> str:
    """HEARTBEAT.custom_mode as MAVSDK's ``FlightMode`` names it (``UNKNOWN`` for numbers without a name)."""
    mode = mode_from_numbers((value >> 16) & 0xFF, (value >> 24) & 0xFF)
    return MODE_TABLE[mode].mavsdk_name if mode is not None else "UNKNOWN"


def base_mode(mode: Px4Mode, armed: bool) -> int:
    """HEARTBEAT.base_mode as PX4 fills it for a multicopter."""
    flags = MAV_MODE_FLAG_CUSTOM_MODE_ENABLED | MODE_TABLE[mode].base_flags
    return flags | (MAV_MODE_FLAG_SAFETY_ARMED if armed else 0)


def is_armed(base_mode_value: int) -> bool:
    """HEARTBEAT.base_mode's SAFETY_ARMED bit."""
    return bool(base_mode_value & MAV_MODE_FLAG_SAFETY_ARMED)


def mode_allowed(mode: Px4Mode, local_position_valid: bool, global_position_valid: bool) -> bool:
    """Whether PX4 would accept a switch to ``mode`` with the given position estimates."""
    spec = MODE_TABLE[mode]
    if spec.needs_global_position and not global_position_valid:
        return False
    return not (spec.needs_local_position and not local_position_valid)


# ---------------------------------------------------------------------------------------------- framing
MAVLINK2_STX = 0xFD
MAVLINK1_STX = 0xFE
MAVLINK2_HEADER_LEN = 10
MAVLINK1_HEADER_LEN = 6
CHECKSUM_LEN = 2
SIGNATURE_LEN = 13
INCOMPAT_FLAG_SIGNED = 0x01


@dataclass(frozen=True)
class FrameHeader:
    """A frame's sender and message id read from its header, and the frame's bytes (payload not decoded)."""

    system_id: int
    component_id: int
    message_id: int
    frame: bytes


def frame_length(data: bytes, i: int) -> int | None:
    """Length [bytes] of the MAVLink 1 or 2 frame starting at ``data[i]`` (header, payload, CRC, signature);
    None when no start marker is there or the header is cut off. Whether the frame fits is the caller's check."""
    n = len(data)
    stx = data[i]
    if stx == MAVLINK2_STX and i + MAVLINK2_HEADER_LEN <= n:
        signed = data[i + 2] & INCOMPAT_FLAG_SIGNED
        return MAVLINK2_HEADER_LEN + data[i + 1] + CHECKSUM_LEN + (SIGNATURE_LEN if signed else 0)
    if stx == MAVLINK1_STX and i + MAVLINK1_HEADER_LEN <= n:
        return MAVLINK1_HEADER_LEN + data[i + 1] + CHECKSUM_LEN
    return None


def message_id(frame: bytes) -> int:
    """The message id in a whole frame's header (24 bits in MAVLink 2, 8 in MAVLink 1)."""
    if frame[0] == MAVLINK2_STX:
        return frame[7] | (frame[8] << 8) | (frame[9] << 16)
    return frame[5]


def split_frames(datagram: bytes) -> tuple[list[FrameHeader], int]:
    """Cut a UDP datagram into whole MAVLink frames; returns them and the number of bytes skipped as garbage.

    A truncated frame at the end is garbage; bytes before a start marker are skipped. CRC is not checked here
    (the frames are logged as received; the few that are decoded are CRC-checked by pymavlink).
    """
    frames: list[FrameHeader] = []
    skipped = 0
    i = 0
    n = len(datagram)
    while i < n:
        total = frame_length(datagram, i)
        if total is None:
            skipped += 1
            i += 1
            continue
        if i + total > n:
            skipped += n - i
            break
        frame = bytes(datagram[i : i + total])
        sender = 5 if frame[0] == MAVLINK2_STX else 3
        frames.append(FrameHeader(frame[sender], frame[sender + 1], message_id(frame), frame))
        i += total
    return frames, skipped
