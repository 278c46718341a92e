"""An agent's decoding of the neighbour states it hears, each relayed copy decoded once however many carry it.

With relaying on (improved mode), every state message carries copies of the states its sender heard (multi-hop
knowledge, :mod:`vehicle_agents.core.relay`), and a drone hearing a dozen neighbours receives the same copies many
times over: every neighbour relays the same few origins' newest states, and keeps relaying them for a few ticks.
In ``circle`` a message carries ~5 copies with their edge points (~3 kB), and only about one copy in six a drone
receives is one it has not already received byte for byte in this tick or the previous one. Decoding each whole
message decodes and validates all of them again: most of an agent's decoding time.

:class:`HeardStateDecoder` decodes a message's own fields with the copies left as raw bytes, decodes each copy's
bytes once (with every check :class:`~comms.messages.NeighbourState` makes) and remembers it for two polls, then
builds the :class:`~comms.messages.NeighbourState`, whose own checks run as in a whole decode. Equal bytes decode
to equal states, so the result is the whole decode's; a message is dropped and counted when the whole decode would
drop it (the reason of a bad copy is the copy's).
"""

from __future__ import annotations

from typing import Annotated, Any

import msgspec

from comms.messages import (
    MAX_PAYLOAD_BYTES,
    MAX_RELAYED,
    DecodeStats,
    InvalidMessage,
    NeighbourState,
    decode_with_reason,
)

_KIND = NeighbourState.__name__
_LIMIT_BYTES = MAX_PAYLOAD_BYTES[NeighbourState]


def _field(info: msgspec.structs.FieldInfo) -> tuple[str, object] | tuple[str, object, object]:
    """One field of the mirror: as in :class:`~comms.messages.NeighbourState`, the relayed copies left undecoded."""
    kind = Annotated[list[msgspec.Raw], msgspec.Meta(max_length=MAX_RELAYED)] if info.name == "relayed" else info.type
    if info.default is not msgspec.NODEFAULT:
        return info.name, kind, info.default
    if info.default_factory is not msgspec.NODEFAULT:
        return info.name, kind, msgspec.field(default_factory=info.default_factory)
    return info.name, kind


_CONFIG = NeighbourState.__struct_config__
_StateWithRawCopies = msgspec.defstruct(
    "_StateWithRawCopies", [_field(info) for info in msgspec.structs.fields(NeighbourState)],
    frozen=_CONFIG.frozen, omit_defaults=_CONFIG.omit_defaults, tag_field=_CONFIG.tag_field, tag=_CONFIG.tag)
""":class:`~comms.messages.NeighbourState`'s wire layout, field for field (made from it, so it follows any change),
with the relayed copies undecoded."""

_outer_decoder = msgspec.msgpack.Decoder(_StateWithRawCopies)
_copy_decoder = msgspec.msgpack.Decoder(NeighbourState)
"""A copy decoded as :func:`~comms.messages.decode` does; the reason of a failure comes from there."""
_FIELD_NAMES = tuple(info.name for info in msgspec.structs.fields(NeighbourState))
_RELAYED = _FIELD_NAMES.index("relayed")
_AFTER_RELAYED = _RELAYED + 1


def _with_copies(wire: Any, copies: list[NeighbourState]) -> NeighbourState:
    """The state with ``copies`` in place of the raw ones, every field passed by position: a field the message
    left out holds the very default object a whole decode would give (``omit_defaults`` then leaves it out again
    on encoding), and the state's own checks run as in a whole decode."""
    values = msgspec.structs.astuple(wire)
    return NeighbourState(*values[:_RELAYED], copies, *values[_AFTER_RELAYED:])


class HeardStateDecoder:
    """Decodes state messages into :class:`~comms.messages.NeighbourState`, copies shared across messages.

    Call :meth:`next_poll` once per poll of the inbox: copies decoded in this poll and the previous one are reused.
    Not thread-safe (one per consuming thread, like the poll it serves).
    """

    def __init__(self) -> None:
        self._copies: dict[bytes, NeighbourState] = {}
        self._previous: dict[bytes, NeighbourState] = {}
        self.copies_decoded = 0
        self.copies_reused = 0

    def next_poll(self) -> None:
        """Forget the copies of the poll before the previous one (a copy is relayed for a few ticks at most)."""
        self._previous, self._copies = self._copies, {}

    def decode(self, payload: bytes | memoryview, stats: DecodeStats) -> NeighbourState | None:
        """The state in ``payload``, or None (counted in ``stats`` under the reason) when it does not pass."""
        if len(payload) > _LIMIT_BYTES:
            stats.count_drop(_KIND, "oversized")
            return None
        try:
            wire = _outer_decoder.decode(payload)
        except Exception:  # msgspec.DecodeError / ValidationError: let the whole decode name the reason
            return decode_with_reason(NeighbourState, payload, stats)[0]
        copies: list[NeighbourState] = []
        this_poll, previous_poll = self._copies, self._previous
        for raw in wire.relayed:  # ~7 per message, most met before: the lookups are inlined
            key = bytes(raw)
            copy = this_poll.get(key)
            if copy is None:
                copy = previous_poll.get(key)
                if copy is None:
                    copy = self._decode_copy(key, stats)
                    if copy is None:
                        return None
                    self.copies_decoded += 1
                else:
                    self.copies_reused += 1
                this_poll[key] = copy
            else:
                self.copies_reused += 1
            copies.append(copy)
        try:
            state = _with_copies(wire, copies)
        except InvalidMessage:
            stats.count_drop(_KIND, "invalid")
            return None
        stats.count_ok(_KIND)
        return state

    @staticmethod
    def _decode_copy(raw: bytes, stats: DecodeStats) -> NeighbourState | None:
        """A copy not met in this poll or the previous one, with every check of a whole decode; a bad one is counted
        in ``stats`` under its reason (the good ones are not: they count as part of their carrier)."""
        if len(raw) <= _LIMIT_BYTES:
            try:
                return _copy_decoder.decode(raw)
            except Exception:  # msgspec.DecodeError / ValidationError, InvalidMessage: classified below
                pass
        reason = decode_with_reason(NeighbourState, raw, DecodeStats())[1]
        stats.count_drop(_KIND, reason or "malformed")
        return None
