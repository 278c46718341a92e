"""Receivers grouped on one key: the radio emulator puts one bundle per group of receivers per delivery cycle.

Why: at 300 drones × 20 Hz the emulator's cost beyond taking the states in is per Zenoh put (≈19 µs of CPU per
bundle over its Python thread and Zenoh's ``app`` and ``tx`` threads, docs/BENCHMARKS.md), and with one bundle per
receiver per cycle it made up to 16 000 puts a second. A group of ``RADIO_GROUP_SIZE`` receivers gets one
``RadioGroupBundle`` on ``floodwatch/<m>/radio/group/<g>``: every message due to any member, each once, and per
member the indices of the entries that are its own. Every member subscribes to its group's key and keeps only its
selection, so what each receiver hears is still exactly what the radio model decided for that directed link (the
drops, delays and counters stay per link; the group only shares the Zenoh sample).

Groups are fixed by vehicle id (``group_of``), not by position: only the emulator knows true positions, and a group
that followed them would make agents resubscribe as they fly and lose what was put in between. Ids are given by
role and rank (a boundary group's drones are consecutive along the ring), so consecutive ids mostly fly within
range of each other and a group's union of messages is far smaller than the sum of its members' deliveries (300
drones on a 10 m grid, groups of 8 along a row: ≈55 messages a period for 8 × 17.5 deliveries). Where they do not,
a bundle carries more of the others' entries, never other deliveries. A member could read the other members'
selections; the agents are ours and keep only their own.

The bytes are framed from entries encoded once per message (:mod:`comms.bundle_wire`), exactly what the codec makes
of the same ``RadioGroupBundle`` (tested).
"""

from __future__ import annotations

from collections.abc import Sequence

import msgspec
import numpy as np

from comms.bundle_wire import array_header
from comms.keys import MissionKeys
from comms.link_messages import RadioGroupBundle

RADIO_GROUP_SIZE = 8
"""Receivers per group key. Larger groups mean fewer puts but more of the others' entries in every member's
bundle; the ground station's node (id 0) shares group 0 with vehicles 1–7."""

_encoder = msgspec.msgpack.Encoder()
_ENTRIES_KEY = _encoder.encode("entries")
_EMPTY_TAIL = b"\x90" + _ENTRIES_KEY + b"\x90"  # empty selections, the entries key, empty entries


def group_of(receiver_id: int) -> int:
    """The group whose key carries ``receiver_id``'s deliveries."""
    return int(receiver_id) // RADIO_GROUP_SIZE


def group_inbox_key(keys: MissionKeys, receiver_id: int) -> str:
    """The key a receiver subscribes to for what the radio delivers to it (shared with its group)."""
    return keys.radio_group(group_of(receiver_id))


def group_head(t_s: float) -> bytes:
    """Everything of a ``RadioGroupBundle`` at ``t_s`` before its selections (the same for every group of one
    delivery cycle)."""
    empty = _encoder.encode(RadioGroupBundle(t_s=t_s, selections=[], entries=[]))
    if not empty.endswith(_EMPTY_TAIL):
        raise AssertionError("RadioGroupBundle's fields must end with selections, then entries")
    return empty[: -len(_EMPTY_TAIL)]


def group_bundle_bytes(head: bytes, selections: list[tuple[int, list[int]]], entries: Sequence[bytes]) -> bytes:
    """A whole ``RadioGroupBundle`` from ``group_head(t_s)``, the members' selections and entries from
    ``bundle_wire.encode_entry``."""
    return b"".join((head, _encoder.encode(selections), _ENTRIES_KEY, array_header(len(entries)), *entries))


def framed_group_bundles(t_s: float, receivers: Sequence[int], starts: Sequence[int], ends: Sequence[int],
                         message_ids: np.ndarray, entries: np.ndarray) -> list[tuple[int, bytes]]:
    """One delivery cycle's deliveries as one ``RadioGroupBundle`` per group: [(group, bytes), ...].

    The deliveries come sorted by receiver (ascending) and, within one, by delivery time: receiver
    ``receivers[k]`` gets ``message_ids[starts[k]:ends[k]]``, whose encoded entries are the same rows of
    ``entries``. Each group's entries are the distinct messages its members get, in message order; each member's
    selection lists its messages' indices in its delivery order."""
    member_group = np.asarray(receivers, dtype=np.int64) // RADIO_GROUP_SIZE
    counts = np.asarray(ends, dtype=np.int64) - np.asarray(starts, dtype=np.int64)
    delivery_group = np.repeat(member_group, counts)
    first_message = int(message_ids.min())
    span = int(message_ids.max()) - first_message + 1
    unique, first, inverse = np.unique(delivery_group * span + (message_ids - first_message), return_index=True,
                                       return_inverse=True)
    unique_group = unique // span
    group_start = np.searchsorted(unique_group, unique_group)
    local = (inverse.reshape(-1) - group_start[inverse.reshape(-1)]).tolist()
    shared = entries[first].tolist()
    entry_bounds = [0, *(np.flatnonzero(np.diff(unique_group)) + 1).tolist(), unique.size]
    member_bounds = [0, *(np.flatnonzero(np.diff(member_group)) + 1).tolist(), member_group.size]
    groups = member_group[member_bounds[:-1]].tolist()
    head = group_head(t_s)
    out: list[tuple[int, bytes]] = []
    for k, group in enumerate(groups):
        members = range(member_bounds[k], member_bounds[k + 1])
        selections = [(receivers[m], local[starts[m]:ends[m]]) for m in members]
        out.append((group, group_bundle_bytes(head, selections, shared[entry_bounds[k]:entry_bounds[k + 1]])))
    return out


def selected_entries(bundle: RadioGroupBundle, receiver_id: int) -> list[tuple[int, bytes]]:
    """The (sender_id, payload) entries of ``bundle`` that are ``receiver_id``'s, in its delivery order ([] when the
    bundle holds nothing for it). Raises IndexError on a selection pointing outside the entries."""
    for member, indices in bundle.selections:
        if member == receiver_id:
            entries = bundle.entries
            for i in indices:
                if i < 0:
                    raise IndexError("negative radio bundle selection")
            return [entries[i] for i in indices]
    return []
