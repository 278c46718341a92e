"""A re-sent offboard setpoint, recognised from its bytes without decoding (pure).

MAVSDK re-sends the newest offboard setpoint by itself at 20 Hz of wall time (PX4 wants one at least every
``COM_OF_LOSS_T``). While a paced simulation clock stands still, waiting for a slow agent, those re-sends all arrive at
the same simulated instant and say what the vehicle already holds: they would refresh the setpoint's time stamp to
the time it already has. Only ``time_boot_ms``, the sequence number and so the CRC differ from one re-send to the
next. For a fleet of hundreds of vehicles, decoding and handling each (~100-200 µs in Python) was most of the fleet
process's cost while the clock waited. :func:`setpoint_content` reduces a datagram holding exactly one unsigned
MAVLink 2 SET_POSITION_TARGET_LOCAL_NED with a good CRC to the bytes that carry its meaning; the link skips a
datagram whose content equals that of the datagram it handled last, at the same simulated time.
"""

from __future__ import annotations

from pymavlink.dialects.v20 import common as mavlink
from pymavlink.generator.mavcrc import x25crc

from comms.px4 import CHECKSUM_LEN, MAVLINK2_HEADER_LEN, MAVLINK2_STX, message_id

SETPOINT_MSG_ID = mavlink.MAVLINK_MSG_ID_SET_POSITION_TARGET_LOCAL_NED
_CRC_EXTRA = bytes((mavlink.MAVLink_set_position_target_local_ned_message.crc_extra,))
_SEQ = 4
_TIME_BOOT_MS_BYTES = 4
"""``time_boot_ms`` (uint32) is the payload's first field: the largest fields come first on the wire."""


def setpoint_content(datagram: bytes) -> bytes | None:
    """Everything of the datagram but its sequence number, ``time_boot_ms`` and CRC, when it is exactly one
    unsigned MAVLink 2 SET_POSITION_TARGET_LOCAL_NED frame whose CRC checks; None for anything else."""
    n = len(datagram)
    if n < MAVLINK2_HEADER_LEN + CHECKSUM_LEN or datagram[0] != MAVLINK2_STX or datagram[2] != 0:
        return None
    end = MAVLINK2_HEADER_LEN + datagram[1]
    if end + CHECKSUM_LEN != n or message_id(datagram) != SETPOINT_MSG_ID:
        return None
    crc = x25crc(datagram[1:end])
    crc.accumulate(_CRC_EXTRA)
    if crc.crc != datagram[end] | datagram[end + 1] << 8:
        return None
    payload_start = min(end, MAVLINK2_HEADER_LEN + _TIME_BOOT_MS_BYTES)
    return datagram[1:_SEQ] + datagram[_SEQ + 1:MAVLINK2_HEADER_LEN] + datagram[payload_start:end]


class RepeatedSetpoints:
    """The content and simulated time of the datagram a link handled last; says whether the next one repeats it."""

    def __init__(self) -> None:
        self._content: bytes | None = None
        self._t_s = float("nan")
        self.skipped = 0

    def repeats(self, content: bytes | None, t_s: float) -> bool:
        """True (and counted) when ``content`` is a setpoint equal to the last one handled, at the same time."""
        if content is not None and content == self._content and t_s == self._t_s:
            self.skipped += 1
            return True
        return False

    def handled(self, content: bytes | None, t_s: float) -> None:
        """The link handled a datagram (``content`` None: not a lone setpoint) at simulated time ``t_s``."""
        self._content, self._t_s = content, t_s
