"""The radio between lockstep vehicles: who has heard what, delivered through :class:`comms.radio_model.RadioModel`.

Every control step each vehicle broadcasts one :class:`NeighbourInfo`; the radio model decides from TRUE positions
which receivers hear it and when. A receiver keeps the newest message per sender (highest step index), exactly as
the agents' neighbour table does over Zenoh; the age a control law sees is the time since the sender stamped it.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from comms.radio_model import RadioModel
from vehicle_agents.control.types import NeighbourInfo


class RadioLink:
    """Messages in flight and the newest one heard per (receiver, sender) pair (imperative shell of the model)."""

    def __init__(self, model: RadioModel, vehicle_ids: list[int], keep_s: float) -> None:
        self.model = model
        self.vehicle_ids = np.asarray(vehicle_ids, dtype=np.int64)
        n = len(vehicle_ids)
        self.latest_seq = np.full((n, n), -1, dtype=np.int64)
        self.keep_s = keep_s
        self._sent: dict[int, tuple[float, list[NeighbourInfo | None]]] = {}
        self._pending_t = np.zeros(0)
        self._pending_s = np.zeros(0, dtype=np.int64)
        self._pending_r = np.zeros(0, dtype=np.int64)
        self._pending_q = np.zeros(0, dtype=np.int64)
        self._aged_t_s = math.nan
        self._aged: dict[tuple[int, int], NeighbourInfo] = {}
        self.heard_total = 0
        self.lost_total = 0

    def broadcast(self, seq: int, t_s: float, positions_enu_m: NDArray[np.float64], messages: list[NeighbourInfo | None]) -> None:
        """Everyone with a message (``None``: silent, e.g. lost vehicle) broadcasts at ``t_s``."""
        senders = np.array([i for i, m in enumerate(messages) if m is not None], dtype=np.int64)
        self._sent[seq] = (t_s, messages)
        if senders.size == 0:
            return
        tx = self.model.broadcast(positions_enu_m, t_s, seq, vehicle_ids=self.vehicle_ids, senders=senders)
        s, r, due = tx.heard()
        self.heard_total += int(s.size)
        self.lost_total += tx.lost_count
        self._pending_t = np.concatenate([self._pending_t, due])
        self._pending_s = np.concatenate([self._pending_s, s])
        self._pending_r = np.concatenate([self._pending_r, r])
        self._pending_q = np.concatenate([self._pending_q, np.full(s.shape, seq, dtype=np.int64)])

    def deliver(self, t_s: float) -> None:
        """Hand over every message due by ``t_s`` (newest seq wins per pair) and forget old ones."""
        due = self._pending_t <= t_s + 1e-9
        if np.any(due):
            np.maximum.at(self.latest_seq, (self._pending_r[due], self._pending_s[due]), self._pending_q[due])
            keep = ~due
            self._pending_t, self._pending_s = self._pending_t[keep], self._pending_s[keep]
            self._pending_r, self._pending_q = self._pending_r[keep], self._pending_q[keep]
        for seq in [q for q, (sent_t, _) in self._sent.items() if sent_t < t_s - self.keep_s]:
            del self._sent[seq]

    def heard_by(self, receiver: int, t_s: float) -> list[NeighbourInfo]:
        """What ``receiver`` (row index) currently knows of its neighbours, each aged to ``t_s``.

        A message's age depends only on when it was sent, so each (seq, sender) is aged once per ``t_s`` and the
        same value is shared by every receiver (they are frozen).
        """
        if t_s != self._aged_t_s:
            self._aged_t_s = t_s
            self._aged = {}
        out: list[NeighbourInfo] = []
        row = self.latest_seq[receiver]
        for sender in np.flatnonzero(row >= 0).tolist():
            seq = int(row[sender])
            aged = self._aged.get((seq, sender))
            if aged is None:
                sent = self._sent.get(seq)
                if sent is None or sent[1][sender] is None:
                    continue
                sent_t, messages = sent
                aged = replace(messages[sender], age_s=max(t_s - sent_t, 0.0))
                self._aged[(seq, sender)] = aged
            out.append(aged)
        return out
