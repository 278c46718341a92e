"""The range-limited radio as a pure model: who hears whom, and when.

A real swarm radio delivers a broadcast only to vehicles within range, loses some packets and delays the rest.
The paper's control laws (eqs 8-10) sum only over neighbours a drone can hear, so the radio decides which terms
exist at all. This module decides that from the simulator's TRUE positions (never from what a drone claims in its
message), so a drone with a drifting odometry still has the neighbours physics gives it.

Loss has three independent causes, combined per (message, receiver) link as ``1 - Π(1 - p)``: the Bernoulli
``loss_probability`` (the good state's loss when bursts are on), Gilbert–Elliott bursts per directed link
(:mod:`comms.burst_loss`: ``burst_loss_probability`` while the link is in its bad state, on the sender's mission
clock) and distance, ``edge_loss_probability * (d / range_m) ** edge_loss_exponent``, rising toward the range
limit as the signal fades. A bandwidth limit per sender (``bandwidth_bytes_per_s``) is applied by each engine
before the model, through :mod:`comms.byte_budget`.

Everything here is pure and deterministic: the random draws (loss, jitter, burst states) are a counter-based hash
of ``(seed, sender id, receiver id, message seq or time cell, stream)`` (:mod:`comms.counter_draws`), not a
stateful generator. Two consequences the engines rely on:

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
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from comms.burst_loss import BurstLoss
from comms.counter_draws import uniform_draw

if TYPE_CHECKING:
    from mission_plan.scenario_schema import RadioSpec

__all__ = ["BurstLoss", "RadioModel", "Transmission", "radio_model_of", "uniform_draw"]

GROUND_NODE_ID = 0
"""The ground station's id as a receiver on the radio (vehicle ids start at 1); it never transmits there."""

_STREAM_LOSS = 1
_STREAM_JITTER = 2


def squared_distances(from_m: NDArray[np.float64], to_m: NDArray[np.float64]) -> NDArray[np.float64]:
    """(K, N) squared distances between the rows of ``from_m`` (K, D) and ``to_m`` (N, D), summed axis by axis.

    The range gate of every engine goes through here, so all of them decide "in range" with the same arithmetic.
    One (K, N) array per axis instead of a (K, N, D) difference: a quarter of the cost for the emulator's batches.
    """
    if from_m.shape[1] == 0:
        return np.zeros((from_m.shape[0], to_m.shape[0]))
    total = np.subtract.outer(from_m[:, 0], to_m[:, 0])
    np.multiply(total, total, out=total)  # the first axis alone: exactly 0.0 + its square, the same sum
    diff = np.empty_like(total)
    for axis in range(1, from_m.shape[1]):
        np.subtract.outer(from_m[:, axis], to_m[:, axis], out=diff)
        np.multiply(diff, diff, out=diff)
        total += diff
    return total


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
    """A broadcast radio: range gate on true positions, seeded loss (Bernoulli, bursts, distance), latency, jitter.

    ``range_m`` [m]: a receiver hears a sender iff their true distance is <= range_m (SPEC §4: 25 m in `circle`).
    ``loss_probability``: independent per (message, receiver) link. ``latency_s``/``jitter_s`` [s]: see module doc.
    ``burst``: Gilbert–Elliott timing (None: no bursts), with ``burst_loss_probability`` in the bad state.
    ``edge_loss_probability``/``edge_loss_exponent``: the distance term at the range limit and its growth.
    ``bandwidth_bytes_per_s``: each sender's budget (0: unlimited), applied by the engines.
    """

    range_m: float
    loss_probability: float = 0.0
    latency_s: float = 0.0
    jitter_s: float = 0.0
    seed: int = 0
    burst: BurstLoss | None = None
    burst_loss_probability: float = 1.0
    edge_loss_probability: float = 0.0
    edge_loss_exponent: float = 2.0
    bandwidth_bytes_per_s: float = 0.0

    def __post_init__(self) -> None:
        if not (self.range_m >= 0.0):
            raise ValueError(f"radio.range_m: must be >= 0, got {self.range_m}")
        for name, value in (("loss", self.loss_probability), ("burst_loss", self.burst_loss_probability),
                            ("edge_loss", self.edge_loss_probability)):
            if not (0.0 <= value <= 1.0):
                raise ValueError(f"radio.{name}: must be in [0, 1], got {value}")
        for name, value in (("latency_s", self.latency_s), ("jitter_s", self.jitter_s),
                            ("bandwidth_bytes_per_s", self.bandwidth_bytes_per_s)):
            if not (value >= 0.0):
                raise ValueError(f"radio.{name}: must be >= 0, got {value}")
        if not (self.edge_loss_exponent > 0.0):
            raise ValueError(f"radio.edge_loss_exponent: must be > 0, got {self.edge_loss_exponent}")

    @property
    def mean_loss_probability(self) -> float:
        """Average loss at zero distance over the burst process's stationary law (the campaigns' "average loss")."""
        if self.burst is None:
            return self.loss_probability
        bad = self.burst.bad_fraction
        good_loss = self.loss_probability
        bad_loss = 1.0 - (1.0 - good_loss) * (1.0 - self.burst_loss_probability)
        return (1.0 - bad) * good_loss + bad * bad_loss

    def loss_probabilities(self, sender_ids: ArrayLike, receiver_ids: ArrayLike, clock_t_s: ArrayLike,
                           distance_m: ArrayLike | None) -> NDArray[np.float64]:
        """Each link's loss probability (broadcast): Bernoulli, burst state at ``clock_t_s``, distance."""
        shape = np.broadcast_shapes(np.shape(sender_ids), np.shape(receiver_ids), np.shape(clock_t_s),
                                    () if distance_m is None else np.shape(distance_m))
        keep = np.full(shape, 1.0 - self.loss_probability)
        if self.burst is not None and self.burst_loss_probability > 0.0:
            bad = self.burst.bad(self.seed, sender_ids, receiver_ids, clock_t_s)
            keep = keep * np.where(bad, 1.0 - self.burst_loss_probability, 1.0)
        if distance_m is not None and self.edge_loss_probability > 0.0 and self.range_m > 0.0:
            fraction = np.clip(np.asarray(distance_m, dtype=float) / self.range_m, 0.0, 1.0)
            keep = keep * (1.0 - self.edge_loss_probability * fraction ** self.edge_loss_exponent)
        return 1.0 - keep

    def in_range(self, positions_m: ArrayLike) -> NDArray[np.bool_]:
        """(N, N) matrix: ``[i, j]`` is True when j hears i (symmetric, diagonal False) from TRUE positions (N, 2|3)."""
        p = np.asarray(positions_m, dtype=float)
        if p.ndim != 2:
            raise ValueError(f"positions must be (N, 2) or (N, 3), got shape {p.shape}")
        with np.errstate(invalid="ignore"):
            near = squared_distances(p, p) <= self.range_m * self.range_m
        np.fill_diagonal(near, False)
        return near

    def receivers_of(self, sender_index: int, positions_m: ArrayLike) -> NDArray[np.int64]:
        """Indices of the vehicles within range of one sender (O(N), for per-message use)."""
        p = np.asarray(positions_m, dtype=float)
        with np.errstate(invalid="ignore"):
            near = squared_distances(p[sender_index : sender_index + 1], p)[0] <= self.range_m * self.range_m
        near[sender_index] = False
        return np.flatnonzero(near)

    def link_fate(
        self, sender_ids: ArrayLike, receiver_ids: ArrayLike, seq: ArrayLike, t_s: ArrayLike,
        distance_m: ArrayLike | None = None, clock_t_s: ArrayLike | None = None,
    ) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
        """For in-range links (broadcast arrays of vehicle ids and message seq): (delivered, delivery_t_s).

        Pure function of the seed and the arguments; ``delivery_t_s`` is NaN where the packet is lost.
        ``clock_t_s`` is the mission time the burst state is read at (the message's own time stamp; default
        ``t_s``), ``distance_m`` the true link distance for the distance term.
        """
        shape = np.broadcast_shapes(np.shape(sender_ids), np.shape(receiver_ids), np.shape(seq), np.shape(t_s))
        lossy = self.loss_probability > 0.0 or (self.burst is not None and self.burst_loss_probability > 0.0) or (
            distance_m is not None and self.edge_loss_probability > 0.0)
        if lossy:
            clock = t_s if clock_t_s is None else clock_t_s
            p_loss = self.loss_probabilities(sender_ids, receiver_ids, clock, distance_m)
            delivered = uniform_draw(self.seed, sender_ids, receiver_ids, seq, _STREAM_LOSS) >= p_loss
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
        distance = self.link_distances(positions_m, s_idx, r_idx)
        delivered, delivery_t_s = self.link_fate(ids[s_idx], ids[r_idx], seq_arr[s_idx], t_s, distance)
        return Transmission(s_idx.astype(np.int64), r_idx.astype(np.int64), delivered, delivery_t_s)

    def send(
        self, sender_index: int, positions_m: ArrayLike, t_s: float, seq: int, vehicle_ids: ArrayLike | None = None
    ) -> Transmission:
        """One sender's single message (the emulator's per-message path): O(N) instead of O(N^2)."""
        r_idx = self.receivers_of(sender_index, positions_m)
        n = np.asarray(positions_m).shape[0]
        ids = np.arange(n, dtype=np.int64) if vehicle_ids is None else np.asarray(vehicle_ids, dtype=np.int64)
        s_idx = np.full(r_idx.shape, sender_index, dtype=np.int64)
        distance = self.link_distances(positions_m, s_idx, r_idx)
        delivered, delivery_t_s = self.link_fate(ids[sender_index], ids[r_idx], seq, t_s, distance)
        return Transmission(s_idx, r_idx.astype(np.int64), delivered, delivery_t_s)

    def send_many(
        self,
        sender_index: ArrayLike,
        positions_m: ArrayLike,
        t_s: ArrayLike,
        seq: ArrayLike,
        vehicle_ids: ArrayLike | None = None,
        clock_t_s: ArrayLike | None = None,
    ) -> Transmission:
        """K messages from the given position rows (e.g. everything the emulator received in one tick) at once:
        O(K N) vectorised. ``t_s``, ``seq`` and ``clock_t_s`` (each message's own mission time, for the burst
        state; default ``t_s``) are scalars or (K,); rows carry ``message_index`` into the K."""
        p = np.asarray(positions_m, dtype=float)
        senders = np.asarray(sender_index, dtype=np.int64).reshape(-1)
        k = senders.size
        ids = np.arange(p.shape[0], dtype=np.int64) if vehicle_ids is None else np.asarray(vehicle_ids, dtype=np.int64)
        with np.errstate(invalid="ignore"):
            near = squared_distances(p[senders], p) <= self.range_m * self.range_m
        near[np.arange(k), senders] = False
        m_idx, r_idx = np.nonzero(near)
        s_idx = senders[m_idx]
        seq_k = np.broadcast_to(np.asarray(seq, dtype=np.int64), (k,))
        t_k = np.broadcast_to(np.asarray(t_s, dtype=float), (k,))
        clock_k = t_k if clock_t_s is None else np.broadcast_to(np.asarray(clock_t_s, dtype=float), (k,))
        distance = self.link_distances(p, s_idx, r_idx)
        delivered, delivery_t_s = self.link_fate(ids[s_idx], ids[r_idx], seq_k[m_idx], t_k[m_idx], distance,
                                                 clock_k[m_idx])
        return Transmission(s_idx, r_idx.astype(np.int64), delivered, delivery_t_s, m_idx.astype(np.int64))

    @property
    def loses_packets(self) -> bool:
        """Whether any loss term is on (otherwise every in-range link delivers and ``link_fate`` draws nothing)."""
        return self.loss_probability > 0.0 or (self.burst is not None and self.burst_loss_probability > 0.0) or (
            self.edge_loss_probability > 0.0)

    def heard_by(self, positions_m: NDArray[np.float64], sender_rows: NDArray[np.int64]) -> NDArray[np.bool_]:
        """(N, K): ``[j, k]`` is True when position row j hears a message from row ``sender_rows[k]`` (never the
        sender itself): ``send_many``'s range gate, receiver-major. The same arithmetic: ``a - b`` is exactly
        ``-(b - a)`` in floating point, so every squared distance, hence every decision, is the same."""
        with np.errstate(invalid="ignore"):
            near = squared_distances(positions_m, positions_m[sender_rows]) <= self.range_m * self.range_m
        near[sender_rows, np.arange(sender_rows.size)] = False
        return near

    def link_distances(self, positions_m: ArrayLike, s_idx: NDArray[np.int64],
                   r_idx: NDArray[np.int64]) -> NDArray[np.float64] | None:
        """True distance of each (sender, receiver) row, computed only when the distance term is on."""
        if self.edge_loss_probability <= 0.0:
            return None
        p = np.asarray(positions_m, dtype=float)
        d = p[s_idx] - p[r_idx]
        return np.sqrt(np.einsum("kj,kj->k", d, d))


def radio_model_of(spec: RadioSpec, seed: int) -> RadioModel:
    """The model of a scenario's ``[radio]`` table, seeded with the mission seed (both engines build it here)."""
    burst = BurstLoss(spec.burst_mean_s, spec.burst_gap_s) if spec.burst_mean_s > 0.0 else None
    return RadioModel(
        range_m=spec.range_m, loss_probability=spec.loss, latency_s=spec.latency_s, jitter_s=spec.jitter_s,
        seed=seed, burst=burst, burst_loss_probability=spec.burst_loss, edge_loss_probability=spec.edge_loss,
        edge_loss_exponent=spec.edge_loss_exponent, bandwidth_bytes_per_s=spec.bandwidth_bytes_per_s,
    )
