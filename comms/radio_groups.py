"""Receivers grouped on one key: the radio emulator puts one bundle per group of receivers per delivery cycle.

Why: at 300 drones × 20 Hz the emulator's cost beyond taking the states in is per Zenoh put (≈19 µs of CPU per
bundle over its Python thread and Zenoh's ``app`` and ``tx`` threads, docs/BENCHMARKS.md), and with one bundle per
receiver per cycle it made up to 16 000 puts a second. A group of ``RADIO_GROUP_SIZE`` receivers gets one
``RadioGroupBundle`` on ``floodwatch/<m>/radio/group/<g>``: every message due to any member, each once, and per
member (``receivers``, ``counts``) its run of ``indices`` into those entries. Every member subscribes to its
group's key and keeps only its own run, so what each receiver hears is still exactly what the radio model decided
for that directed link (the drops, delays and counters stay per link; the group only shares the Zenoh sample).

Groups are fixed by vehicle id (``group_of``), not by position: only the emulator knows true positions, and a group
that followed them would make agents resubscribe as they fly and lose what was put in between. Ids are given by
role and rank (a boundary group's drones are consecutive along the ring), so consecutive ids mostly fly within
range of each other and a group's union of messages is far smaller than the sum of its members' deliveries (300
drones on a 10 m grid, numbered row by row: 82 messages a period for 16 × 17.5 deliveries). Where they do not, a
bundle carries more of the others' entries, never other deliveries. A member could read the other members'
runs; the agents are ours and keep only their own.

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

RADIO_GROUP_SIZE = 16
"""Receivers per group key. Larger groups mean fewer puts but more of the others' entries in every member's
bundle (300 drones on the 10 m grid: 82 messages a period for a member's own 17.5 with 16, 50 with 8; 16 cost
0.67–0.87 of 8's CPU per delivery, docs/BENCHMARKS.md). The ground station's node (id 0) shares group 0 with
vehicles 1–15."""

_encoder = msgspec.msgpack.Encoder()
_COUNTS_KEY, _INDICES_KEY, _ENTRIES_KEY = (_encoder.encode(name) for name in ("counts", "indices", "entries"))
_EMPTY_TAIL = b"".join((b"\x90", _COUNTS_KEY, b"\x90", _INDICES_KEY, b"\x90", _ENTRIES_KEY, b"\x90"))
_DENSE_CELLS = 1 << 20  # above this many (group, message) cells the distinct pairs are found by sorting instead


def group_of(receiver_id: int) -> int:
    """The group whose key carries ``receiver_id``'s deliveries."""
    return int(receiver_id) // RADIO_GROUP_SIZE


def group_inbox_key(keys: MissionKeys, receiver_id: int) -> str:
    """The key a receiver subscribes to for what the radio delivers to it (shared with its group)."""
    return keys.radio_group(group_of(receiver_id))


def group_head(t_s: float) -> bytes:
    """Everything of a ``RadioGroupBundle`` at ``t_s`` before its ``receivers`` list (the same for every group of
    one delivery cycle)."""
    empty = _encoder.encode(RadioGroupBundle(t_s=t_s, receivers=[], counts=[], indices=[], entries=[]))
    if not empty.endswith(_EMPTY_TAIL):
        raise AssertionError("RadioGroupBundle's fields must end with receivers, counts, indices, entries")
    return empty[: -len(_EMPTY_TAIL)]


def group_bundle_bytes(head: bytes, receivers: list[int], counts: list[int], indices: list[int],
                       entries: Sequence[bytes]) -> bytes:
    """A whole ``RadioGroupBundle`` from ``group_head(t_s)``, its lists, and entries from
    ``bundle_wire.encode_entry``."""
    return b"".join((head, _encoder.encode(receivers), _COUNTS_KEY, _encoder.encode(counts), _INDICES_KEY,
                     _encoder.encode(indices), _ENTRIES_KEY, array_header(len(entries)), *entries))


def _distinct_per_group(group_rank: np.ndarray, message_ids: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For deliveries (group rank ascending, message id): (each delivery's index among its group's distinct
    messages, ordered by message id; a delivery of each distinct (group, message) pair, group-major; the group rank
    of each pair)."""
    first_message = int(message_ids.min())
    span = int(message_ids.max()) - first_message + 1
    groups = int(group_rank[-1]) + 1
    cell = group_rank * span + (message_ids - first_message)
    if groups * span <= _DENSE_CELLS:  # a mark per (group, message) cell and a running count: no sort
        present = np.zeros(groups * span, dtype=bool)
        present[cell] = True
        running = np.cumsum(present)
        row_start = np.concatenate(([0], running[span - 1::span][:-1]))
        local = running[cell] - 1 - row_start[group_rank]
        pairs = np.flatnonzero(present)
        delivery_of = np.empty(groups * span, dtype=np.int64)
        delivery_of[cell] = np.arange(cell.size)  # any delivery of the pair: they all carry the same entry
        return local, delivery_of[pairs], pairs // span
    unique, first, inverse = np.unique(cell, return_index=True, return_inverse=True)
    pair_group = unique // span
    group_start = np.searchsorted(pair_group, pair_group)
    inverse = inverse.reshape(-1)
    return inverse - group_start[inverse], first, pair_group


def framed_group_bundles(t_s: float, receivers: np.ndarray, message_ids: np.ndarray,
                         entries: np.ndarray) -> list[tuple[int, bytes]]:
    """One delivery cycle's deliveries as one ``RadioGroupBundle`` per group: [(group, bytes), ...].

    Row ``i`` delivers message ``message_ids[i]`` (encoded entry ``entries[i]``) to ``receivers[i]``; rows come
    sorted by receiver (ascending) and, within one, by delivery time. Each group's entries are the distinct messages
    its members get, in message order; each member's indices list its messages in its delivery order."""
    group = receivers // RADIO_GROUP_SIZE
    member_bounds = np.flatnonzero(np.diff(receivers)) + 1
    group_changes = np.flatnonzero(np.diff(group)) + 1
    group_rank = np.zeros(receivers.size, dtype=np.int64)
    group_rank[group_changes] = 1
    local, first, pair_group = _distinct_per_group(np.cumsum(group_rank), message_ids)
    member_starts = np.concatenate(([0], member_bounds))
    delivery_bounds = [0, *group_changes.tolist(), receivers.size]
    entry_bounds = np.searchsorted(pair_group, np.arange(len(delivery_bounds))).tolist()
    members_of = np.searchsorted(member_starts, delivery_bounds).tolist()  # group k: members members_of[k]..[k+1]
    member_list = receivers[member_starts].tolist()
    count_list = np.diff(np.concatenate((member_starts, [receivers.size]))).tolist()
    shared, local_list = entries[first].tolist(), local.tolist()
    head = group_head(t_s)
    return [(group_id, group_bundle_bytes(head, member_list[members_of[k]:members_of[k + 1]],
                                          count_list[members_of[k]:members_of[k + 1]],
                                          local_list[delivery_bounds[k]:delivery_bounds[k + 1]],
                                          shared[entry_bounds[k]:entry_bounds[k + 1]]))
            for k, group_id in enumerate(group[delivery_bounds[:-1]].tolist())]


def selected_entries(bundle: RadioGroupBundle, receiver_id: int) -> list[tuple[int, bytes]]:
    """The (sender_id, payload) entries of ``bundle`` that are ``receiver_id``'s, in its delivery order ([] when the
    bundle holds nothing for it). Raises ValueError on lists that do not fit together, IndexError on an index
    outside the entries."""
    receivers, counts, indices = bundle.receivers, bundle.counts, bundle.indices
    if len(counts) != len(receivers) or sum(counts) != len(indices) or min(counts, default=0) < 0:
        raise ValueError("radio group bundle: receivers, counts and indices do not match")
    try:
        position = receivers.index(receiver_id)
    except ValueError:
        return []
    offset = sum(counts[:position])
    entries = bundle.entries
    mine = indices[offset:offset + counts[position]]
    if min(mine, default=0) < 0:
        raise IndexError("negative radio bundle index")
    return [entries[i] for i in mine]
