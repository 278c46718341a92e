"""The radio between lockstep vehicles, on the wire format: each broadcast encoded once, decoded once, delivered by
:class:`comms.radio_model.RadioModel`.

Every control step each drone's onboard core hands over its :class:`~comms.messages.NeighbourState`; it is encoded
as on Zenoh (MessagePack) and decoded once, and that one decoded message goes to every receiver the model lets hear
it (range on TRUE positions, seeded loss by the message's own ``seq``, as the radio emulator draws it, latency and
jitter; bursts on the message's own time stamp; each sender's byte budget), so what only travels on the wire (the
ring radius in ``extras``, the subsampled edge points) reaches the control laws in lockstep exactly as over processes. The ground station hears every decoded broadcast, losslessly,
as it does on the public state keys.

Each broadcast is also signed and checked once as on Zenoh (:mod:`comms.signing`; the sender is the drone, the
timestamp its mission time in microseconds), so both engines pay the same per-message cost and a message the
check refused would be dropped alike. Nobody else can reach this in-memory radio, so its key is a random one of
this run; it never changes what is delivered.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from comms.byte_budget import SenderBudgets
from comms.messages import DecodeStats, NeighbourState, decode, encode
from comms.radio_model import RadioModel
from comms.signing import KEY_BYTES, MissionKey, Signer, Verifier
from vehicle_agents.core.neighbours import Inbox


class InMemoryRadio:
    """Messages in flight between N vehicles (rows of the positions given to :meth:`broadcast`)."""

    def __init__(self, model: RadioModel, vehicle_ids: Sequence[int]) -> None:
        self.model = model
        self.vehicle_ids = np.asarray(vehicle_ids, dtype=np.int64)
        self.stats = DecodeStats()
        key = MissionKey(os.urandom(KEY_BYTES))
        self._signers = {int(vid): Signer(key, int(vid)) for vid in self.vehicle_ids}
        self.verifier = Verifier(key)
        self._round = 0
        self._sent: dict[int, list[NeighbourState | None]] = {}
        self._pending_t = np.zeros(0)
        self._pending_s = np.zeros(0, dtype=np.int64)
        self._pending_r = np.zeros(0, dtype=np.int64)
        self._pending_q = np.zeros(0, dtype=np.int64)
        self.heard_total = 0
        self.lost_total = 0
        self.bytes_sent = 0
        self.budgets = SenderBudgets(model.bandwidth_bytes_per_s)

    def broadcast(
        self, t_s: float, positions_enu_m: NDArray[np.float64], messages: Sequence[NeighbourState | None]
    ) -> list[NeighbourState | None]:
        """Everyone with a message (None: silent) broadcasts at ``t_s``; returns the decoded messages (what a
        listener on the public keys receives, the ones over the sender's byte budget included)."""
        decoded: list[NeighbourState | None] = []
        on_air: list[int] = []
        for i, message in enumerate(messages):
            if message is None:
                decoded.append(None)
                continue
            t_us = round(t_s * 1e6)
            payload = self._signers[message.sender_id].sign(encode(message), t_us)
            self.bytes_sent += len(payload)
            body = self.verifier.check(payload, message.sender_id, t_us).body
            state = None if body is None else decode(NeighbourState, body, self.stats)
            decoded.append(state)
            if state is not None and self.budgets.admit(int(self.vehicle_ids[i]), len(payload), state.t_s):
                on_air.append(i)
        senders = np.array(on_air, dtype=np.int64)
        if senders.size == 0:
            return decoded
        seqs = np.array([m.seq if m is not None else 0 for m in decoded], dtype=np.int64)
        tx = self.model.broadcast(positions_enu_m, t_s, seqs, vehicle_ids=self.vehicle_ids, senders=senders)
        s, r, due = tx.heard()
        self.heard_total += int(s.size)
        self.lost_total += tx.lost_count
        if s.size:
            self._sent[self._round] = decoded
            self._pending_t = np.concatenate([self._pending_t, due])
            self._pending_s = np.concatenate([self._pending_s, s])
            self._pending_r = np.concatenate([self._pending_r, r])
            self._pending_q = np.concatenate([self._pending_q, np.full(s.shape, self._round, dtype=np.int64)])
        self._round += 1
        return decoded

    def deliver(self, t_s: float) -> list[Inbox]:
        """Each receiver's inbox: every message due by ``t_s`` (its core keeps the newest per sender)."""
        n = len(self.vehicle_ids)
        states: list[list[NeighbourState]] = [[] for _ in range(n)]
        due = self._pending_t <= t_s + 1e-9
        if np.any(due):
            for rnd, sender, receiver in zip(self._pending_q[due].tolist(), self._pending_s[due].tolist(),
                                             self._pending_r[due].tolist()):
                message = self._sent[rnd][sender]
                if message is not None:
                    states[receiver].append(message)
            keep = ~due
            self._pending_t, self._pending_s = self._pending_t[keep], self._pending_s[keep]
            self._pending_r, self._pending_q = self._pending_r[keep], self._pending_q[keep]
            live = set(self._pending_q.tolist())
            for rnd in [q for q in self._sent if q not in live]:
                del self._sent[rnd]
        return [Inbox(states=s) if s else _EMPTY for s in states]


_EMPTY = Inbox()
