"""Authentication tags on swarm messages: who may speak, and only once (pure; no sockets, no clocks, no files).

The ground station's commands and every drone's state message travel over Zenoh, where anyone who reaches a router
can publish. As MAVLink 2 signing does for MAVLink, each signed payload carries a tag that only holders of the
mission key can compute, over the message, the sender and a timestamp:

    signed payload = body | C4 1D | version (1 B) | sender (u32, big-endian) | timestamp_us (u64, big-endian) | tag (16 B)

* ``body`` is the message exactly as :func:`comms.messages.encode` made it (a MessagePack map);
* the 31 bytes after it are one MessagePack ``bin 8`` object of 29 bytes (``C4 1D`` is its header), so an outside
  MessagePack reader that streams objects sees the message first and the signature block second;
* ``sender`` is the vehicle id, or :data:`GROUND_STATION` (0xFFFFFFFF) for the ground station;
* ``timestamp_us`` is the sender's wall clock in microseconds since the Unix epoch, strictly increasing per signer
  (the next one is at least the previous + 1), so it is also a sequence number;
* ``tag`` is HMAC-SHA256 (RFC 2104) with the 32-byte mission key over every byte before it (body, block header,
  version, sender, timestamp), truncated to its first 128 bits (RFC 2104 §5 allows truncation to ≥ 80 bits;
  MAVLink 2 keeps 48).

A receiver accepts a payload only when the tag is right, the sender is one it accepts on that key (the ground
station on the command key, vehicle ``i`` on ``uav/i/state``), the timestamp is newer than the newest it accepted
from that sender (a replay of anything it already heard fails here) and within ``window_s`` of its own clock (a
replay captured earlier and sent to a receiver that never heard the original fails here). Checking costs one
HMAC over the message (~1-2 µs for a state) and one dict lookup; see docs/BENCHMARKS.md.
"""

from __future__ import annotations

import enum
import hashlib
import hmac
import struct
from dataclasses import dataclass, field
from typing import NamedTuple

KEY_BYTES = 32
TAG_BYTES = 16
VERSION = 1
GROUND_STATION = 0xFFFF_FFFF
"""The sender number of the ground station (vehicle ids are below it)."""

_BLOCK = struct.Struct(">2sBIQ")  # bin-8 header, version, sender, timestamp_us
_BIN8_HEADER = bytes((0xC4, _BLOCK.size - 2 + TAG_BYTES))
TRAILER_BYTES = _BLOCK.size + TAG_BYTES
"""Bytes a signature adds to a message (31)."""
DEFAULT_WINDOW_S = 30.0
"""How far a timestamp may lie from the receiver's clock [s]: wide enough for radio delay on a loaded host, narrow
enough that a captured message is useless soon after (MAVLink 2 allows one minute for a new stream)."""


class Rejection(enum.Enum):
    """Why a receiver dropped a payload; the value names the counter and the event."""

    UNSIGNED = "unsigned"
    BAD_TAG = "bad_tag"
    WRONG_SENDER = "wrong_sender"
    REPLAYED = "replayed"
    OUT_OF_WINDOW = "out_of_window"


@dataclass(frozen=True, repr=False)
class MissionKey:
    """The shared secret of one mission (32 random bytes); ``repr`` never shows it."""

    secret: bytes

    def __post_init__(self) -> None:
        if len(self.secret) != KEY_BYTES:
            raise ValueError(f"a mission key is {KEY_BYTES} bytes, got {len(self.secret)}")

    def __repr__(self) -> str:
        return "MissionKey(<secret>)"


class Tagger:
    """HMAC-SHA256 with one key, truncated to :data:`TAG_BYTES`, with the key's two padded hash states computed
    once (RFC 2104: H((K ^ opad) | H((K ^ ipad) | m))): a tag then costs two state copies and two short hashes,
    a third of what ``hmac.digest`` spends setting up the key on every call."""

    def __init__(self, key: MissionKey) -> None:
        block = key.secret.ljust(hashlib.sha256().block_size, b"\0")
        self._inner = hashlib.sha256(bytes(b ^ 0x36 for b in block))
        self._outer = hashlib.sha256(bytes(b ^ 0x5C for b in block))

    def tag(self, data: bytes | memoryview) -> bytes:
        inner = self._inner.copy()
        inner.update(data)
        outer = self._outer.copy()
        outer.update(inner.digest())
        return outer.digest()[:TAG_BYTES]


def sign(key: MissionKey | Tagger, body: bytes, sender: int, timestamp_us: int) -> bytes:
    """``body`` with its signature block appended (see the module docstring for the layout)."""
    tagger = key if isinstance(key, Tagger) else Tagger(key)
    signed_part = body + _BLOCK.pack(_BIN8_HEADER, VERSION, sender, timestamp_us)
    return signed_part + tagger.tag(signed_part)


@dataclass(frozen=True)
class SignatureBlock:
    """What a signed payload claims: its sender, its timestamp [µs since the epoch], and where the body ends."""

    sender: int
    timestamp_us: int
    body_bytes: int


def _unpack_block(payload: bytes) -> tuple[int, int] | None:
    """(sender, timestamp_us) of the signature block at the end of ``payload``, None when there is none."""
    if len(payload) <= TRAILER_BYTES:
        return None
    header, version, sender, timestamp_us = _BLOCK.unpack_from(payload, len(payload) - TRAILER_BYTES)
    if header != _BIN8_HEADER or version != VERSION:
        return None
    return sender, timestamp_us


def read_block(payload: bytes) -> SignatureBlock | None:
    """The signature block of ``payload`` without checking the tag; None when there is none (an unsigned message)."""
    block = _unpack_block(payload)
    return None if block is None else SignatureBlock(block[0], block[1], len(payload) - TRAILER_BYTES)


def unsigned_body(payload: bytes) -> bytes:
    """The message part of a signed payload, unchecked (for read-only listeners that hold no key)."""
    return payload if _unpack_block(payload) is None else payload[: len(payload) - TRAILER_BYTES]


class Verdict(NamedTuple):
    """The outcome of one check: the body when accepted, else the reason; ``sender`` is the claimed one (or None)."""

    body: bytes | None
    reason: Rejection | None
    sender: int | None
    timestamp_us: int = 0


class Signer:
    """Signs one sender's messages with strictly increasing timestamps (a clock that stands still or steps back
    still yields fresh ones)."""

    def __init__(self, key: MissionKey, sender: int) -> None:
        self.sender = sender
        self._tagger = Tagger(key)
        self._last_us = 0

    def sign(self, body: bytes, now_us: int) -> bytes:
        self._last_us = max(now_us, self._last_us + 1)
        return sign(self._tagger, body, self.sender, self._last_us)


@dataclass
class Verifier:
    """Checks signed payloads and remembers the newest timestamp accepted per sender.

    ``counts`` holds how many payloads were dropped per :class:`Rejection` and ``accepted`` how many passed. Not
    thread-safe: one verifier per consuming thread (the callbacks on Zenoh's threads never verify).
    """

    key: MissionKey
    window_s: float = DEFAULT_WINDOW_S
    newest_us: dict[int, int] = field(default_factory=dict)
    counts: dict[Rejection, int] = field(default_factory=lambda: {r: 0 for r in Rejection})
    accepted: int = 0

    def __post_init__(self) -> None:
        self._tagger = Tagger(self.key)
        self._window_us = self.window_s * 1e6

    def check(self, payload: bytes, allowed_sender: int | None, now_us: int) -> Verdict:
        """Accept ``payload`` from ``allowed_sender`` (None: any sender) or say why not."""
        n = len(payload)
        if n <= TRAILER_BYTES:
            return self._reject(Rejection.UNSIGNED, None)
        header, version, sender, timestamp_us = _BLOCK.unpack_from(payload, n - TRAILER_BYTES)
        if header != _BIN8_HEADER or version != VERSION:
            return self._reject(Rejection.UNSIGNED, None)
        end = n - TAG_BYTES
        view = memoryview(payload)
        if not hmac.compare_digest(self._tagger.tag(view[:end]), view[end:]):
            return self._reject(Rejection.BAD_TAG, sender, timestamp_us)
        if allowed_sender is not None and sender != allowed_sender:
            return self._reject(Rejection.WRONG_SENDER, sender, timestamp_us)
        if timestamp_us <= self.newest_us.get(sender, -1):
            return self._reject(Rejection.REPLAYED, sender, timestamp_us)
        if abs(timestamp_us - now_us) > self._window_us:
            return self._reject(Rejection.OUT_OF_WINDOW, sender, timestamp_us)
        self.newest_us[sender] = timestamp_us
        self.accepted += 1
        return Verdict(payload[: n - TRAILER_BYTES], None, sender, timestamp_us)

    def _reject(self, reason: Rejection, sender: int | None, timestamp_us: int = 0) -> Verdict:
        self.counts[reason] += 1
        return Verdict(None, reason, sender, timestamp_us)

    def dropped_total(self) -> int:
        return sum(self.counts.values())


def sender_name(sender: int | None) -> str:
    """``gcs``, a vehicle id, or ``unknown`` for an unsigned payload (for event lines)."""
    if sender is None:
        return "unknown"
    return "gcs" if sender == GROUND_STATION else str(sender)
