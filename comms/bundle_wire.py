"""A ``RadioBundle``'s bytes assembled from entries encoded once per message, not once per delivery.

The radio emulator hands every state to ~17 receivers (300 drones on a 10 m grid, 25 m range). Encoding a
``RadioBundle`` per receiver re-encodes each ``(sender_id, payload)`` pair for every receiver that gets it and
first builds a Python tuple per delivery. MessagePack lets a bundle be framed instead: the struct's fixed head
(schema tag, ``t_s``), an array header with the entry count, then the entries, each already encoded once when
its message was decided. The bytes are exactly those ``encode(RadioBundle(t_s, entries))`` produces (the tests
compare them), so receivers decode bundles with the ordinary decoder.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence

import msgspec

from comms.link_messages import RadioBundle

_entry_encoder = msgspec.msgpack.Encoder()
_bundle_encoder = msgspec.msgpack.Encoder()
_EMPTY_ARRAY = b"\x90"
_ARRAY16 = struct.Struct(">BH")
_ARRAY32 = struct.Struct(">BI")


def encode_entry(sender_id: int, payload: bytes) -> bytes:
    """One bundle entry, ``[sender_id, payload]``, as MessagePack (encoded once, shared by every receiver)."""
    return _entry_encoder.encode((sender_id, payload))


def encode_entries(sender_ids: Sequence[int], payloads: Sequence[bytes]) -> list[bytes]:
    """``encode_entry`` of each pair, in one loop (a batch of states decided at once)."""
    return list(map(_entry_encoder.encode, zip(sender_ids, payloads)))


_FIXARRAY_HEADERS = [bytes((0x90 | count,)) for count in range(16)]


def array_header(count: int) -> bytes:
    """The MessagePack header of an array of ``count`` items (fixarray, array 16 or array 32)."""
    if count < 16:
        return _FIXARRAY_HEADERS[count]
    if count < 1 << 16:
        return _ARRAY16.pack(0xDC, count)
    return _ARRAY32.pack(0xDD, count)


def bundle_head(t_s: float) -> bytes:
    """Everything of a ``RadioBundle`` at ``t_s`` before its entries' array header (the same for every receiver
    of one delivery cycle)."""
    empty = _bundle_encoder.encode(RadioBundle(t_s=t_s, entries=[]))
    if not empty.endswith(_EMPTY_ARRAY):
        raise AssertionError("RadioBundle's entries must be its last field")
    return empty[: -len(_EMPTY_ARRAY)]


def bundle_bytes(head: bytes, entries: Sequence[bytes]) -> bytes:
    """A whole ``RadioBundle`` from ``bundle_head(t_s)`` and entries from ``encode_entry``."""
    return b"".join((head, array_header(len(entries)), *entries))

