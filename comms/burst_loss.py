"""Gilbert–Elliott bursty loss per directed link, evaluated without a stateful chain (pure).

Real radios lose packets in bursts (a drone banks behind another, a motor's noise, a Wi-Fi neighbour): after one
loss the next is likely too. The Gilbert–Elliott model says each directed link is in a good or a bad state, with its
own loss probability in each; here the state is a continuous-time Markov chain in mission seconds with mean sojourn
``burst_mean_s`` in the bad state and ``gap_mean_s`` in the good state.

Why no per-link state is kept: the radio's draws are a counter-based hash (:func:`comms.radio_model.uniform_draw`)
so that the lockstep engine and the Zenoh radio emulator give the same fate to the same message whatever order and
whichever subset of messages each processes. A chain advanced message by message would break that (its state
would depend on which messages the engine happened to see for that link). Instead the chain is written in its
uniformised form: a two-state chain with rates ``a`` (good→bad) and ``b`` (bad→good) has the generator
``(a + b)(Π − I)`` where every row of ``Π`` is the stationary law ``π = (b, a) / (a + b)``; so the state at time
``t`` is the stationary label drawn at the last event before ``t`` of a Poisson process of rate ``ν = a + b``. That
process is laid out on cells of width ``1 / ν`` from the hash (event count Poisson(1), positions uniform, labels
Bernoulli(π_bad)), so the state of link (s, r) at time t is a pure function of ``(seed, s, r, t)`` and costs a
look at one or two cells on average. The one approximation: a cell holds at most :data:`MAX_EVENTS_PER_CELL`
events (P(Poisson(1) > 8) ≈ 1e-6).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from comms.counter_draws import uniform_draw

MAX_EVENTS_PER_CELL = 8
_MAX_CELLS_BACK = 64  # P(64 empty cells) = e^-64: the search never ends for lack of an event in practice
_STREAM_COUNT = 11
_STREAM_POSITION = 12
_STREAM_LABEL = 13
_POISSON_ONE_CDF = np.cumsum([math.exp(-1.0) / math.factorial(k) for k in range(MAX_EVENTS_PER_CELL + 1)])
_POISSON_ONE_CDF[-1] = 1.0


@dataclass(frozen=True)
class BurstLoss:
    """Gilbert–Elliott link states: mean burst (bad sojourn) and mean gap between bursts (good sojourn) [s]."""

    burst_mean_s: float
    gap_mean_s: float

    def __post_init__(self) -> None:
        if not (self.burst_mean_s > 0.0):
            raise ValueError(f"radio.burst_mean_s: must be > 0, got {self.burst_mean_s}")
        if not (self.gap_mean_s > 0.0):
            raise ValueError(f"radio.burst_gap_s: must be > 0, got {self.gap_mean_s}")

    @property
    def bad_fraction(self) -> float:
        """Stationary probability of the bad state: ``burst / (burst + gap)``."""
        return self.burst_mean_s / (self.burst_mean_s + self.gap_mean_s)

    @property
    def cell_s(self) -> float:
        """Width of one hash cell [s]: the mean time between state refreshes, ``1 / (1/burst + 1/gap)``."""
        return 1.0 / (1.0 / self.burst_mean_s + 1.0 / self.gap_mean_s)

    def bad(self, seed: int, sender_ids: ArrayLike, receiver_ids: ArrayLike, t_s: ArrayLike) -> NDArray[np.bool_]:
        """Whether each directed link (sender → receiver) is in its bad state at mission time ``t_s`` (broadcast)."""
        s, r, t = np.broadcast_arrays(np.asarray(sender_ids, dtype=np.int64), np.asarray(receiver_ids, dtype=np.int64),
                                      np.asarray(t_s, dtype=float))
        s, r, t = s.ravel(), r.ravel(), t.ravel()
        out = np.zeros(t.shape, dtype=bool)
        pending = np.arange(t.size)
        cell = np.floor(t / self.cell_s).astype(np.int64)
        slots = np.arange(MAX_EVENTS_PER_CELL, dtype=np.int64)
        for back in range(_MAX_CELLS_BACK):
            if pending.size == 0:
                break
            ps, pr, pc = s[pending], r[pending], cell[pending] - back
            count = np.searchsorted(_POISSON_ONE_CDF, uniform_draw(seed, ps, pr, pc, _STREAM_COUNT), side="right")
            counter = pc[:, None] * MAX_EVENTS_PER_CELL + slots[None, :]
            offset = uniform_draw(seed, ps[:, None], pr[:, None], counter, _STREAM_POSITION)
            valid = slots[None, :] < count[:, None]
            if back == 0:
                valid &= (pc[:, None] + offset) * self.cell_s <= t[pending][:, None]
            found = valid.any(axis=1)
            last = np.argmax(np.where(valid, offset, -1.0), axis=1)
            hit = pending[found]
            label_counter = counter[found, last[found]]
            out[hit] = uniform_draw(seed, s[hit], r[hit], label_counter, _STREAM_LABEL) < self.bad_fraction
            pending = pending[~found]
        if pending.size:
            out[pending] = uniform_draw(seed, s[pending], r[pending], cell[pending], _STREAM_LABEL) < self.bad_fraction
        return out.reshape(np.broadcast_shapes(np.shape(sender_ids), np.shape(receiver_ids), np.shape(t_s)))
