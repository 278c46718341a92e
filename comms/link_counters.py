"""Per directed link (sender, receiver) totals of the radio emulator: delivered and lost, reported once a second.

Why a module of its own: the emulator counts every link of every message, 100 000 a second at 300 drones, but
reads the totals only for its ``radio/stats`` report. So a batch held as a delivery matrix
(:mod:`comms.radio_matrix`) is only noted here and counted when the totals are read (``fold``), in one pass over
all the batches noted since: the per-cycle cost is a list append. Batches decided in rows are counted at once.

Each vehicle id gets a slot the first time it is seen and keeps it, so the totals survive vehicles dying and the
truth's order changing.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from comms.radio_matrix import stacked_columns

_FOLD_AFTER = 256  # matrices noted before they are counted anyway (a long stats period holds no more in memory)


class LinkCounters:
    """Delivered / lost totals per (sender id, receiver id), indexed by slot."""

    def __init__(self) -> None:
        self.delivered = np.zeros((0, 0), dtype=np.int64)
        self.lost = np.zeros((0, 0), dtype=np.int64)
        self._ids: list[int] = []
        self._slot: dict[int, int] = {}
        self._slot_of_id = np.zeros(0, dtype=np.int64)  # vehicle id -> slot, for the ids of noted matrices
        self._noted: list[tuple[NDArray[np.int64], NDArray[np.bool_]]] = []
        self._noted_lost: list[tuple[NDArray[np.int64], NDArray[np.int64]]] = []

    def slots_of(self, vehicle_ids: list[int]) -> NDArray[np.int64]:
        """The slot of each id (new ids get new slots)."""
        return np.array([self._slot_index(int(v)) for v in vehicle_ids], dtype=np.int64)

    def add_rows(self, sender_slots: NDArray[np.int64], receiver_slots: NDArray[np.int64],
                 delivered: NDArray[np.bool_]) -> None:
        """Count links given row by row (flattened cells: numpy's fast path for ``add.at`` is one-dimensional)."""
        size = self.delivered.shape[0]
        cell = sender_slots * size + receiver_slots
        if delivered.all():
            np.add.at(self.delivered.reshape(-1), cell, 1)
            return
        np.add.at(self.delivered.reshape(-1), cell[delivered], 1)
        np.add.at(self.lost.reshape(-1), cell[~delivered], 1)

    def note_matrix(self, sender_ids: NDArray[np.int64], delivered: NDArray[np.bool_],
                    lost_senders: NDArray[np.int64] | None = None, lost_receivers: NDArray[np.int64] | None = None) -> None:
        """Note a batch: ``delivered[receiver id, k]`` from ``sender_ids[k]`` (kept as given: not to be changed
        after), and the (sender id, receiver id) of its lost links. Every id must already have a slot."""
        self._noted.append((sender_ids, delivered))
        if lost_senders is not None and lost_receivers is not None and lost_senders.size:
            self._noted_lost.append((lost_senders, lost_receivers))
        if len(self._noted) >= _FOLD_AFTER:
            self.fold()

    def fold(self) -> None:
        """Count the noted batches into the totals."""
        if not self._noted and not self._noted_lost:
            return
        size = self.delivered.shape[0]
        slot_of = self._slot_of_id
        if self._noted:
            matrix = stacked_columns([d for _, d in self._noted])
            senders = np.concatenate([s for s, _ in self._noted])
            cells = np.flatnonzero(matrix)
            receivers = cells // senders.size
            counted = slot_of[senders[cells - receivers * senders.size]] * size + slot_of[receivers]
            np.add.at(self.delivered.reshape(-1), counted, 1)  # no size² temporary: a long list of cells is cheap
        if self._noted_lost:
            lost_cells = np.concatenate([slot_of[s] * size + slot_of[r] for s, r in self._noted_lost])
            np.add.at(self.lost.reshape(-1), lost_cells, 1)
        self._noted, self._noted_lost = [], []

    def links(self) -> list[list[int]]:
        """[sender id, receiver id, delivered, lost] of every link with traffic (after ``fold``)."""
        self.fold()
        s_idx, r_idx = np.nonzero((self.delivered + self.lost) > 0)
        ids = np.asarray(self._ids, dtype=np.int64)
        return np.stack([ids[s_idx], ids[r_idx], self.delivered[s_idx, r_idx], self.lost[s_idx, r_idx]],
                        axis=1).tolist()

    def _slot_index(self, vehicle_id: int) -> int:
        slot = self._slot.get(vehicle_id)
        if slot is not None:
            return slot
        self.fold()  # the noted cells are numbered by the current size
        slot = len(self._ids)
        self._slot[vehicle_id] = slot
        self._ids.append(vehicle_id)
        if slot >= self.delivered.shape[0]:
            size = max(16, 2 * slot)
            for name in ("delivered", "lost"):
                old = getattr(self, name)
                grown = np.zeros((size, size), dtype=np.int64)
                grown[: old.shape[0], : old.shape[1]] = old
                setattr(self, name, grown)
        if 0 <= vehicle_id < (1 << 16):
            if vehicle_id >= self._slot_of_id.size:
                grown_ids = np.zeros(max(vehicle_id + 1, 2 * self._slot_of_id.size), dtype=np.int64)
                grown_ids[: self._slot_of_id.size] = self._slot_of_id
                self._slot_of_id = grown_ids
            self._slot_of_id[vehicle_id] = slot
        return slot
