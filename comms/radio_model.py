"""The range-limited radio as a pure model: who hears whom, and when.

A real swarm radio delivers a broadcast only to vehicles within range, loses some packets and delays the rest.
The paper's control laws (eqs 8-10) sum only over neighbours a drone can hear, so the radio decides which terms
exist at all. This module decides that from the simulator's TRUE positions (never from what a drone claims in its
message), so a drone with a drifting odometry still has the neighbours physics gives it.

Everything here is pure and deterministic: the random draws (loss and jitter) are a counter-based hash of
``(seed, sender id, receiver id, message seq, stream)``, not a stateful generator. Two consequences the engines
rely on:

* the lockstep engine and the Zenoh radio emulator give the same fate to the same message for the same seed,
  whatever order they process messages in;
* a test can recompute the expected fate of any message independently.

Latency model: ``delay_s = latency_s + jitter_s * u`` with ``u ~ U[0, 1)``, i.e. ``latency_s`` is the minimum
one-way delay and ``jitter_s`` the width of the extra uniform delay (mean ``latency_s + jitter_s / 2``). Jitter can
reorder messages from one sender; receivers keep the newest ``seq`` (see ``NeighbourTable``).

Distances are Euclidean over the columns given: pass (N, 2) east/north for a horizontal range or (N, 3) ENU for
a slant range. A NaN position (vehicle without truth, e.g. dead) is out of range of everyone.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

_STREAM_LOSS = 1
_STREAM_JITTER = 2
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_TWO_POW_53 = float(2**53)


def _mix(x: NDArray[np.uint64]) -> NDArray[np.uint64]:
    """splitmix64 finaliser on an array (uint64 arithmetic wraps, which is what the hash wants)."""
    x = x + _GOLDEN
    x = (x ^ (x >> np.uint64(30))) * _MIX1
    x = (x ^ (x >> np.uint64(27))) * _MIX2
    return x ^ (x >> np.uint64(31))


def _as_u64(values: ArrayLike) -> NDArray[np.uint64]:
    return np.asarray(values, dtype=np.int64).astype(np.uint64)


def uniform_draw(seed: int, sender_ids: ArrayLike, receiver_ids: ArrayLike, seq: ArrayLike, stream: int) -> NDArray[np.float64]:
    """Deterministic U[0, 1) draws, one per broadcast element of the inputs (a counter-based RNG).

    The same ``(seed, sender, receiver, seq, stream)`` always gives the same number; neighbouring tuples give
    independent-looking numbers (splitmix64 chained over the fields).
    """
    s, r, q = np.broadcast_arrays(_as_u64(sender_ids), _as_u64(receiver_ids), _as_u64(seq))
    with np.errstate(over="ignore"):
        h = _mix(np.full(s.shape, np.uint64(seed & 0xFFFFFFFFFFFFFFFF), dtype=np.uint64))
        h = _mix(h ^ s)
        h = _mix(h ^ r)
        h = _mix(h ^ q)
        h = _mix(h ^ np.uint64(stream))
    return (h >> np.uint64(11)).astype(np.float64) / _TWO_POW_53


@dataclass(frozen=True)
class Transmission:
    """The fate of one round of broadcasts: one row per (sender, receiver) pair that was within range.

    Indices refer to rows of the positions array given to the model. ``delivered`` is False for a lost packet;
    ``delivery_t_s`` is the source time plus the link delay (NaN where lost).
    """

    sender_index: NDArray[np.int64]
    receiver_index: NDArray[np.int64]
    delivered: NDArray[np.bool_]
    delivery_t_s: NDArray[np.float64]
    message_index: NDArray[np.int64] | None = None  # send_many: which of the K messages each row belongs to

    @property
    def heard_count(self) -> int:
        return int(np.count_nonzero(self.delivered))

    @property
    def lost_count(self) -> int:
        return int(self.delivered.size - np.count_nonzero(self.delivered))

    def heard(self) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
        """(sender_index, receiver_index, delivery_t_s) of the packets that arrive."""
        m = self.delivered
        return self.sender_index[m], self.receiver_index[m], self.delivery_t_s[m]


@dataclass(frozen=True)
class RadioModel:
    """A broadcast radio: range gate on true positions, seeded Bernoulli loss, fixed latency plus uniform jitter.

    ``range_m`` [m]: a receiver hears a sender iff their true distance is <= range_m (SPEC §4: 25 m in `circle`).
    ``loss_probability``: independent per (message, receiver) link. ``latency_s``/``jitter_s`` [s]: see module doc.
    """

    range_m: float
    loss_probability: float = 0.0
    latency_s: float = 0.0
    jitter_s: float = 0.0
    seed: int = 0

    def __post_init__(self) -> None:
        if not (self.range_m >= 0.0):
            raise ValueError(f"radio.range_m: must be >= 0, got {self.range_m}")
        if not (0.0 <= self.loss_probability <= 1.0):
            raise ValueError(f"radio.loss: must be in [0, 1], got {self.loss_probability}")
        if not (self.latency_s >= 0.0):
            raise ValueError(f"radio.latency_s: must be >= 0, got {self.latency_s}")
        if not (self.jitter_s >= 0.0):
            raise ValueError(f"radio.jitter_s: must be >= 0, got {self.jitter_s}")

    def in_range(self, positions_m: ArrayLike) -> NDArray[np.bool_]:
        """(N, N) matrix: ``[i, j]`` is True when j hears i (symmetric, diagonal False) from TRUE positions (N, 2|3)."""
        p = np.asarray(positions_m, dtype=float)
        if p.ndim != 2:
            raise ValueError(f"positions must be (N, 2) or (N, 3), got shape {p.shape}")
        diff = p[:, None, :] - p[None, :, :]
        dist2 = np.einsum("ijk,ijk->ij", diff, diff)
        with np.errstate(invalid="ignore"):
            near = dist2 <= self.range_m * self.range_m
        np.fill_diagonal(near, False)
        return near

    def receivers_of(self, sender_index: int, positions_m: ArrayLike) -> NDArray[np.int64]:
        """Indices of the vehicles within range of one sender (O(N), for per-message use)."""
        p = np.asarray(positions_m, dtype=float)
        d = p - p[sender_index]
        with np.errstate(invalid="ignore"):
            near = np.einsum("ij,ij->i", d, d) <= self.range_m * self.range_m
        near[sender_index] = False
        return np.flatnonzero(near)

    def link_fate(
        self, sender_ids: ArrayLike, receiver_ids: ArrayLike, seq: ArrayLike, t_s: ArrayLike
    ) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
        """For in-range links (broadcast arrays of vehicle ids and message seq): (delivered, delivery_t_s).

        Pure function of the seed and the arguments; ``delivery_t_s`` is NaN where the packet is lost.
        """
        shape = np.broadcast_shapes(np.shape(sender_ids), np.shape(receiver_ids), np.shape(seq), np.shape(t_s))
        if self.loss_probability > 0.0:
            delivered = uniform_draw(self.seed, sender_ids, receiver_ids, seq, _STREAM_LOSS) >= self.loss_probability
            delivered = np.broadcast_to(delivered, shape).copy()
        else:
            delivered = np.ones(shape, dtype=bool)
        delay_s = np.full(shape, self.latency_s, dtype=float)
        if self.jitter_s > 0.0:
            delay_s = delay_s + self.jitter_s * uniform_draw(self.seed, sender_ids, receiver_ids, seq, _STREAM_JITTER)
        delivery_t_s = np.where(delivered, np.asarray(t_s, dtype=float) + delay_s, np.nan)
        return delivered, delivery_t_s

    def broadcast(
        self,
        positions_m: ArrayLike,
        t_s: float,
        seq: ArrayLike,
        vehicle_ids: ArrayLike | None = None,
        senders: ArrayLike | None = None,
    ) -> Transmission:
        """Every sender (or the boolean/index subset ``senders``) broadcasts once at ``t_s``; who hears it and when.

        ``positions_m``: TRUE positions (N, 2|3). ``seq``: scalar or (N,) message sequence numbers (the lockstep
        engine passes its step index). ``vehicle_ids`` (N,) seed the per-link draws so that the outcome does not
        depend on row order (default: row index).
        """
        near = self.in_range(positions_m)
        n = near.shape[0]
        ids = np.arange(n, dtype=np.int64) if vehicle_ids is None else np.asarray(vehicle_ids, dtype=np.int64)
        if senders is not None:
            mask = np.zeros(n, dtype=bool)
            mask[np.asarray(senders)] = True
            near &= mask[:, None]
        s_idx, r_idx = np.nonzero(near)
        seq_arr = np.broadcast_to(np.asarray(seq, dtype=np.int64), (n,))
        delivered, delivery_t_s = self.link_fate(ids[s_idx], ids[r_idx], seq_arr[s_idx], t_s)
        return Transmission(s_idx.astype(np.int64), r_idx.astype(np.int64), delivered, delivery_t_s)

    def send(
        self, sender_index: int, positions_m: ArrayLike, t_s: float, seq: int, vehicle_ids: ArrayLike | None = None
    ) -> Transmission:
        """One sender's single message (the emulator's per-message path): O(N) instead of O(N^2)."""
        r_idx = self.receivers_of(sender_index, positions_m)
        n = np.asarray(positions_m).shape[0]
        ids = np.arange(n, dtype=np.int64) if vehicle_ids is None else np.asarray(vehicle_ids, dtype=np.int64)
        delivered, delivery_t_s = self.link_fate(ids[sender_index], ids[r_idx], seq, t_s)
        s_idx = np.full(r_idx.shape, sender_index, dtype=np.int64)
        return Transmission(s_idx, r_idx.astype(np.int64), delivered, delivery_t_s)

    def send_many(
        self,
        sender_index: ArrayLike,
        positions_m: ArrayLike,
        t_s: ArrayLike,
        seq: ArrayLike,
        vehicle_ids: ArrayLike | None = None,
    ) -> Transmission:
        """K messages from the given position rows (e.g. everything the emulator received in one tick) at once:
        O(K N) vectorised. ``t_s`` and ``seq`` are scalars or (K,); rows carry ``message_index`` into the K."""
        p = np.asarray(positions_m, dtype=float)
        senders = np.asarray(sender_index, dtype=np.int64).reshape(-1)
        k = senders.size
        ids = np.arange(p.shape[0], dtype=np.int64) if vehicle_ids is None else np.asarray(vehicle_ids, dtype=np.int64)
        d = p[None, :, :] - p[senders][:, None, :]
        with np.errstate(invalid="ignore"):
            near = np.einsum("kij,kij->ki", d, d) <= self.range_m * self.range_m
        near[np.arange(k), senders] = False
        m_idx, r_idx = np.nonzero(near)
        s_idx = senders[m_idx]
        seq_k = np.broadcast_to(np.asarray(seq, dtype=np.int64), (k,))
        t_k = np.broadcast_to(np.asarray(t_s, dtype=float), (k,))
        delivered, delivery_t_s = self.link_fate(ids[s_idx], ids[r_idx], seq_k[m_idx], t_k[m_idx])
        return Transmission(s_idx, r_idx.astype(np.int64), delivered, delivery_t_s, m_idx.astype(np.int64))
