"""MAVLink 2 bytes <-> messages for one link, without sockets (the h11 shape: bytes in, messages out).

Every UDP datagram is parsed on its own, from a fresh state: a frame never spans datagrams, so garbage at the end
of one datagram can never swallow the frame at the start of the next (pymavlink's stream parser would keep the
partial bytes). Inside a datagram the scanner looks for the MAVLink 2 magic byte, checks the length, the known
message id (an unknown id has no CRC_EXTRA, so its CRC cannot be checked: pymavlink would hand it back as
``UNKNOWN_n`` unchecked; here it is dropped as malformed) and the CRC; on any failure it resumes one byte later,
so a valid frame after garbage in the same datagram is still found.

Then per frame: MAVLink 2 signing when the link requires it (MAV_SIGN_CFG-like: SHA-256 signature over the
secret key and the frame, link id and a 48-bit timestamp that must increase per stream and be no older than a
minute), our own system and component id as sender (a looped-back frame; a companion computer shares our system id), target system / component, and infinities in float
fields. Each drop is counted by reason in :attr:`LinkCodec.drops`.

A datagram "vouches" for its sender (``ParsedDatagram.vouched``) when at least one frame in it passed every check;
only then may the UDP layer move the link's peer address to the datagram's source. PX4 itself latches the peer
address on the first datagram of any content; the stricter rule here is what stops garbage from a stranger from
redirecting telemetry. With signing required, only signed frames vouch.
"""

from __future__ import annotations

import hashlib
import math
from collections import Counter
from dataclasses import dataclass, field

from pymavlink.dialects.v20 import common as mavlink
from pymavlink.generator.mavcrc import x25crc

from comms.px4 import INCOMPAT_FLAG_SIGNED, MAVLINK1_STX, MAVLINK2_HEADER_LEN, MAVLINK2_STX, SIGNATURE_LEN
from comms.px4 import frame_length, message_id

MAGIC_V2 = MAVLINK2_STX
MAGIC_V1 = MAVLINK1_STX
HEADER_LEN_V2 = MAVLINK2_HEADER_LEN
IFLAG_SIGNED = INCOMPAT_FLAG_SIGNED
SIGNING_EPOCH_UNIX_S = 1_420_070_400  # 2015-01-01, the MAVLink signing timestamp origin
SIGNING_TICKS_PER_S = 100_000  # 10 µs units
SIGNING_MAX_AGE_TICKS = 60 * SIGNING_TICKS_PER_S

UNSIGNED_ALLOWED = frozenset({mavlink.MAVLINK_MSG_ID_HEARTBEAT, mavlink.MAVLINK_MSG_ID_RADIO_STATUS})
BROADCAST_TARGET_ALLOWED = frozenset({mavlink.MAVLINK_MSG_ID_PING})

_FLOAT_FIELDS: dict[int, tuple[str, ...]] = {
    msg_id: tuple(n for n, t in zip(cls.fieldnames, cls.fieldtypes) if t in ("float", "double"))
    for msg_id, cls in mavlink.mavlink_map.items()
}


@dataclass(frozen=True)
class ParsedDatagram:
    """The messages a datagram carried that passed every check, and whether it vouches for its sender."""

    messages: list[mavlink.MAVLink_message]
    vouched: bool


@dataclass
class SigningState:
    """MAVLink 2 signing for one link: the secret key, whether incoming frames must be signed, replay state."""

    secret_key: bytes
    required: bool
    link_id: int = 0
    stream_timestamps: dict[tuple[int, int, int], int] = field(default_factory=dict)
    newest_timestamp: int = 0


def signing_timestamp(unix_time_s: float) -> int:
    """MAVLink signing timestamp (10 µs ticks since 2015-01-01) of a Unix time."""
    return max(0, int((unix_time_s - SIGNING_EPOCH_UNIX_S) * SIGNING_TICKS_PER_S))


def parse_signing_key(text: str) -> bytes:
    """A 32-byte signing key from 64 hex digits; raises ValueError with a one-line reason."""
    try:
        key = bytes.fromhex(text.strip())
    except ValueError as exc:
        raise ValueError("signing key must be 64 hex digits") from exc
    if len(key) != 32:
        raise ValueError(f"signing key must be 32 bytes (64 hex digits), got {len(key)} bytes")
    return key


class LinkCodec:
    """Parses datagrams into checked messages and encodes messages into frames for one link of one vehicle."""

    def __init__(self, system_id: int, component_id: int = 1, signing: SigningState | None = None) -> None:
        self.system_id = system_id
        self.component_id = component_id
        self.signing = signing
        self.drops: Counter[str] = Counter()
        self.frames_accepted = 0
        self._decoder = mavlink.MAVLink(None, 0, 0)
        self._encoder = mavlink.MAVLink(None, system_id, component_id)
        if signing is not None:
            self._encoder.signing.secret_key = signing.secret_key
            self._encoder.signing.sign_outgoing = True
            self._encoder.signing.link_id = signing.link_id

    # ---------------------------------------------------------------- inbound
    def parse_datagram(self, data: bytes, unix_time_s: float) -> ParsedDatagram:
        """Split one datagram into frames, check each, decode the good ones."""
        messages: list[mavlink.MAVLink_message] = []
        vouched = False
        for frame in self._split(data):
            msg, vouches = self._check_and_decode(frame, unix_time_s)
            if msg is not None:
                messages.append(msg)
                vouched = vouched or vouches
        return ParsedDatagram(messages, vouched)

    def _split(self, data: bytes) -> list[bytes]:
        frames: list[bytes] = []
        n = len(data)
        i = 0
        in_garbage = False
        while i < n:
            b = data[i]
            if b == MAGIC_V2:
                frame, reason = self._frame_at(data, i)
                if frame is not None:
                    frames.append(frame)
                    i += len(frame)
                    in_garbage = False
                    continue
                self.drops[reason] += 1
                i += 1
                in_garbage = True
                continue
            if b == MAGIC_V1 and i + 1 < n and i + 8 + data[i + 1] <= n:
                self.drops["mavlink1"] += 1
                i += 8 + data[i + 1]
                in_garbage = False
                continue
            if not in_garbage:
                self.drops["garbage"] += 1
                in_garbage = True
            i += 1
        if not data:
            self.drops["empty"] += 1
        return frames

    def _frame_at(self, data: bytes, i: int) -> tuple[bytes | None, str]:
        n = len(data)
        if n - i < HEADER_LEN_V2 + 2:
            return None, "truncated"
        payload_len = data[i + 1]
        incompat = data[i + 2]
        if incompat & ~IFLAG_SIGNED:
            return None, "bad_incompat_flags"
        frame_len = frame_length(data, i)
        if frame_len is None or i + frame_len > n:
            return None, "truncated"
        msg_id = message_id(data[i : i + HEADER_LEN_V2])
        cls = mavlink.mavlink_map.get(msg_id)
        if cls is None:
            return None, "unknown_msgid"
        if payload_len > cls.unpacker.size:
            return None, "bad_length"
        end = i + HEADER_LEN_V2 + payload_len
        crc = x25crc(data[i + 1 : end])
        crc.accumulate(bytes((cls.crc_extra,)))
        if crc.crc != (data[end] | (data[end + 1] << 8)):
            return None, "bad_crc"
        return bytes(data[i : i + frame_len]), ""

    def _check_and_decode(self, frame: bytes, unix_time_s: float) -> tuple[mavlink.MAVLink_message | None, bool]:
        msg_id = message_id(frame)
        src_system, src_component = frame[5], frame[6]
        signed = bool(frame[2] & IFLAG_SIGNED)
        signature_ok = False
        if self.signing is not None and self.signing.required:
            if not signed:
                if msg_id not in UNSIGNED_ALLOWED:
                    self.drops["unsigned"] += 1
                    return None, False
            else:
                reason = self._verify_signature(frame, src_system, src_component, unix_time_s)
                if reason:
                    self.drops[reason] += 1
                    return None, False
                signature_ok = True
        if src_system == self.system_id and src_component == self.component_id:
            self.drops["looped_back"] += 1
            return None, False
        try:
            msg = self._decoder.decode(bytearray(frame))
        except Exception:  # pymavlink raises MAVError or struct errors on payloads it cannot unpack
            self.drops["undecodable"] += 1
            return None, False
        target_system = getattr(msg, "target_system", None)
        if target_system is not None:
            broadcast_ok = target_system == 0 and msg_id in BROADCAST_TARGET_ALLOWED
            if target_system != self.system_id and not broadcast_ok:
                self.drops["wrong_target_system"] += 1
                return None, False
        target_component = getattr(msg, "target_component", None)
        if target_component is not None and target_component not in (0, self.component_id):
            self.drops["wrong_target_component"] += 1
            return None, False
        for name in _FLOAT_FIELDS.get(msg_id, ()):
            value = getattr(msg, name)
            values = value if isinstance(value, list) else (value,)
            if any(math.isinf(v) for v in values):
                self.drops["infinite_field"] += 1
                return None, False
        self.frames_accepted += 1
        requires_signature = self.signing is not None and self.signing.required
        return msg, (signature_ok or not requires_signature)

    def _verify_signature(self, frame: bytes, src_system: int, src_component: int, unix_time_s: float) -> str:
        assert self.signing is not None
        link_id = frame[-SIGNATURE_LEN]
        timestamp = int.from_bytes(frame[-12:-6], "little")
        digest = hashlib.sha256(self.signing.secret_key + frame[:-6]).digest()[:6]
        if digest != frame[-6:]:
            return "bad_signature"
        stream = (src_system, src_component, link_id)
        last = self.signing.stream_timestamps.get(stream)
        now_ticks = max(signing_timestamp(unix_time_s), self.signing.newest_timestamp)
        if last is not None and timestamp <= last:
            return "replayed_signature"
        if last is None and timestamp + SIGNING_MAX_AGE_TICKS < now_ticks:
            return "stale_signature"
        self.signing.stream_timestamps[stream] = timestamp
        self.signing.newest_timestamp = max(self.signing.newest_timestamp, timestamp)
        return ""

    # ---------------------------------------------------------------- outbound
    def encode(self, msg: mavlink.MAVLink_message, unix_time_s: float) -> bytes:
        """Pack one message as the next frame of this link (sequence number, signature when signing)."""
        if self.signing is not None:
            self._encoder.signing.timestamp = max(self._encoder.signing.timestamp, signing_timestamp(unix_time_s))
        data = msg.pack(self._encoder)
        self._encoder.seq = (self._encoder.seq + 1) % 256
        return data

