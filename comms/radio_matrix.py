"""One delivery cycle's deliveries as a (receiver id × message) matrix, framed into group bundles from it.

Why: the free-clock emulator runs a delivery cycle every 5 ms, each with the ~30 states that arrived in it, and at
that size the cost of a cycle is the number of array passes, not the deliveries: the row form (one row per
delivery: due time, receiver, sender, payload, entry, message number; a sort by receiver and due time, then the
group framing's marks and counts) made about twice the passes of the matrix form. When every link of a message has
the same delay (no jitter), a batch of K messages decided together is due at one time, so it is held as a boolean
matrix ``delivered[receiver_id, k]`` and everything a cycle hands out is read off the matrices due: a group's
messages are the columns any member's row marks, a member's run is its row. Rows are indexed by vehicle id,
padded to whole groups of ``RADIO_GROUP_SIZE``, so matrices decided under different truths stack as they are.

The bytes are exactly those :func:`comms.radio_groups.framed_group_bundles` makes of the same deliveries in rows
(tested): entries in message order, each member's indices in its delivery order (due time, then message order).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from comms.radio_groups import RADIO_GROUP_SIZE, group_bundle_bytes, group_head

MAX_MATRIX_ID = 4095
"""Vehicle ids up to this one are held as matrix rows (300 drones: 304 rows); a truth with a larger id is decided
in rows instead, so an odd id never makes a huge matrix."""


def padded_rows(max_vehicle_id: int) -> int:
    """Rows of a delivery matrix whose largest receiver id is ``max_vehicle_id``: whole groups."""
    return (max_vehicle_id // RADIO_GROUP_SIZE + 1) * RADIO_GROUP_SIZE


@dataclass(frozen=True)
class MatrixBatch:
    """Messages decided together and due together: ``delivered[r, k]`` when receiver id ``r`` gets message ``k``.

    ``first_message`` numbers the messages as the row form does (``first_message + k``), so a batch can be turned
    into rows when the relay has to (``as_rows``)."""

    due_s: float
    delivered: NDArray[np.bool_]
    sender_ids: NDArray[np.int64]
    payloads: NDArray[np.object_]
    entries: NDArray[np.object_]
    first_message: int
    count: int  # deliveries marked in ``delivered``

    def as_rows(self) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64], NDArray[np.object_],
                               NDArray[np.object_], NDArray[np.int64]]:
        """The batch as in-flight rows: (due, receiver id, sender id, payload, entry, message number)."""
        receivers, messages = np.nonzero(self.delivered)
        return (np.full(receivers.size, self.due_s), receivers.astype(np.int64), self.sender_ids[messages],
                self.payloads[messages], self.entries[messages], self.first_message + messages)


def stacked_columns(matrices: Sequence[NDArray[np.bool_]]) -> NDArray[np.bool_]:
    """Delivery matrices side by side (rows padded to the tallest), in the given order."""
    if len(matrices) == 1:
        return matrices[0]
    out = np.zeros((max(m.shape[0] for m in matrices), sum(m.shape[1] for m in matrices)), dtype=bool)
    start = 0
    for m in matrices:
        out[: m.shape[0], start:start + m.shape[1]] = m
        start += m.shape[1]
    return out


def _column(batches: Sequence[MatrixBatch], name: str) -> NDArray[np.object_]:
    parts = [getattr(b, name) for b in batches]
    return parts[0] if len(parts) == 1 else np.concatenate(parts)


def framed_matrix_bundles(t_s: float, batches: Sequence[MatrixBatch]) -> list[tuple[int, bytes]]:
    """One ``RadioGroupBundle`` per group with anything due in ``batches`` (in delivery order): [(group, bytes)]."""
    delivered = stacked_columns([b.delivered for b in batches])
    rows, k = delivered.shape
    group_marks = delivered.reshape(rows // RADIO_GROUP_SIZE, RADIO_GROUP_SIZE, k).any(axis=1)  # (group, message)
    local = np.cumsum(group_marks, axis=1)  # a message's 1-based place among its group's entries
    cells = np.flatnonzero(delivered)  # receiver-major, then message order: each member's run in delivery order
    receivers = cells // k
    indices = (local.reshape(-1)[receivers // RADIO_GROUP_SIZE * k + (cells - receivers * k)] - 1).tolist()
    counts = np.bincount(receivers, minlength=rows)
    members = np.flatnonzero(counts)
    group_cells = np.flatnonzero(group_marks)
    entries = _column(batches, "entries")[group_cells % k].tolist()
    per_group = local[:, -1]
    groups = np.flatnonzero(per_group)
    entry_bounds = [0, *np.cumsum(per_group[groups]).tolist()]
    member_bounds = np.searchsorted(members, groups * RADIO_GROUP_SIZE + RADIO_GROUP_SIZE).tolist()
    member_counts = counts[members]
    index_bounds = [0, *np.cumsum(member_counts).tolist()]
    member_list, count_list = members.tolist(), member_counts.tolist()
    head = group_head(t_s)
    out = []
    first_member = 0
    for g, (group, last_member) in enumerate(zip(groups.tolist(), member_bounds)):
        out.append((group, group_bundle_bytes(head, member_list[first_member:last_member],
                                              count_list[first_member:last_member],
                                              indices[index_bounds[first_member]:index_bounds[last_member]],
                                              entries[entry_bounds[g]:entry_bounds[g + 1]])))
        first_member = last_member
    return out


def matrix_deliveries(batches: Sequence[MatrixBatch]) -> dict[int, list[tuple[int, bytes]]]:
    """What ``batches`` (in delivery order) hand each receiver: {receiver id: [(sender id, payload), ...]}."""
    delivered = stacked_columns([b.delivered for b in batches])
    k = delivered.shape[1]
    cells = np.flatnonzero(delivered)
    if cells.size == 0:
        return {}
    receivers, messages = cells // k, cells % k
    senders = _column(batches, "sender_ids")[messages].tolist()
    payloads = _column(batches, "payloads")[messages].tolist()
    bounds = (np.flatnonzero(np.diff(receivers)) + 1).tolist()
    starts, ends = [0, *bounds], [*bounds, receivers.size]
    return {r: list(zip(senders[a:b], payloads[a:b]))
            for r, a, b in zip(receivers[starts].tolist(), starts, ends) if b > a}
