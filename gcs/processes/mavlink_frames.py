"""MAVLink framing and PX4 mode names for the ground station's watcher: pure functions on bytes.

The watcher must keep up with every vehicle's full telemetry stream on one socket, so it does not decode every
frame: it splits a datagram into frames by their headers, reads the sender's system id and message id from the
header bytes, writes each frame to that vehicle's .tlog, and decodes only the few messages the live view needs.
"""

from __future__ import annotations

from dataclasses import dataclass

MAVLINK2_STX = 0xFD
MAVLINK1_STX = 0xFE
_MAVLINK2_HEADER_LEN = 10
_MAVLINK1_HEADER_LEN = 6
_CHECKSUM_LEN = 2
_SIGNATURE_LEN = 13
_INCOMPAT_FLAG_SIGNED = 0x01


@dataclass(frozen=True)
class FrameHeader:
    """What the watcher needs from a frame without decoding its payload."""

    system_id: int
    component_id: int
    message_id: int
    frame: bytes


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
        stx = datagram[i]
        if stx == MAVLINK2_STX and i + _MAVLINK2_HEADER_LEN <= n:
            payload_len = datagram[i + 1]
            signed = datagram[i + 2] & _INCOMPAT_FLAG_SIGNED
            total = _MAVLINK2_HEADER_LEN + payload_len + _CHECKSUM_LEN + (_SIGNATURE_LEN if signed else 0)
            if i + total > n:
                skipped += n - i
                break
            message_id = datagram[i + 7] | (datagram[i + 8] << 8) | (datagram[i + 9] << 16)
            frames.append(FrameHeader(datagram[i + 5], datagram[i + 6], message_id, bytes(datagram[i : i + total])))
            i += total
        elif stx == MAVLINK1_STX and i + _MAVLINK1_HEADER_LEN <= n:
            payload_len = datagram[i + 1]
            total = _MAVLINK1_HEADER_LEN + payload_len + _CHECKSUM_LEN
            if i + total > n:
                skipped += n - i
                break
            frames.append(FrameHeader(datagram[i + 3], datagram[i + 4], datagram[i + 5], bytes(datagram[i : i + total])))
            i += total
        else:
            skipped += 1
            i += 1
    return frames, skipped


_PX4_MAIN_MODES = {1: "MANUAL", 2: "ALTCTL", 3: "POSCTL", 5: "ACRO", 6: "OFFBOARD", 7: "STABILIZED", 8: "RATTITUDE"}
_PX4_AUTO_SUB_MODES = {1: "READY", 2: "TAKEOFF", 3: "LOITER", 4: "MISSION", 5: "RTL", 6: "LAND", 7: "RTGS", 8: "FOLLOW"}
MAV_MODE_FLAG_SAFETY_ARMED = 128


def px4_mode_name(custom_mode: int) -> str:
    """PX4's ``custom_mode = (sub_mode << 24) | (main_mode << 16)`` as the name QGroundControl shows."""
    main_mode = (custom_mode >> 16) & 0xFF
    sub_mode = (custom_mode >> 24) & 0xFF
    if main_mode == 4:
        return "AUTO." + _PX4_AUTO_SUB_MODES.get(sub_mode, str(sub_mode))
    return _PX4_MAIN_MODES.get(main_mode, f"MODE{main_mode}")
