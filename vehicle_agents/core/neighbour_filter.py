"""Each drone's constant-velocity Kalman filter per neighbour, vectorised across neighbours (pure).

The laws of the paper (eqs 8-10) read where a neighbour is now; a radio gives where it was when it spoke, late by
the latency and by every lost packet in between. Each drone therefore keeps, per neighbour, a constant-velocity
estimate ``x = [e, n, ve, vn]`` [m, m/s; mission E, N] with covariance ``P``. A neighbour's message (direct or
relayed) is a measurement of its whole state at the sender's own time stamp ``t_s``: the track is predicted to
that time, then updated (``H = I``); the laws read the track predicted to the control time, so the message's age
counts, not its arrival. Between messages the covariance grows with the process noise (white acceleration of
spectral density ``q`` per axis, the discretised Wiener-process acceleration model):

    F = [[I, dt I], [0, I]],   Q = q [[dt³/3 I, dt²/2 I], [dt²/2 I, dt I]]

A neighbour is dropped when the standard deviation of its predicted position (the larger axis) exceeds a bound:
a gap of a few seconds for a hovering neighbour, and the same rule whatever the message rate. All tracks of one
drone live in one :class:`TrackBank` of arrays, so an update or a prediction is a handful of numpy operations on
(M, 4, 4) arrays whatever the number M of neighbours (≈200 at ``large``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from comms.messages import NeighbourState


@dataclass(frozen=True)
class FilterNoise:
    """Process noise ``accel_psd_m2ps3`` [m²/s³], measurement noise [m, m/s], and the drop bound [m, 1 sigma]."""

    accel_psd_m2ps3: float = 1.0
    position_std_m: float = 0.3
    velocity_std_mps: float = 0.3
    position_bound_m: float = 3.0

    @property
    def measurement_variance(self) -> NDArray[np.float64]:
        p, v = self.position_std_m ** 2, self.velocity_std_mps ** 2
        return np.array([p, p, v, v])


@dataclass(frozen=True)
class TrackBank:
    """Every neighbour track of one drone: ids (M,), estimate time [s] (M,), state (M, 4), covariance (M, 4, 4)."""

    ids: NDArray[np.int64]
    t_s: NDArray[np.float64]
    x: NDArray[np.float64]
    p: NDArray[np.float64]

    def __len__(self) -> int:
        return int(self.ids.size)


_EYE2 = np.eye(2)[None]

EMPTY_BANK = TrackBank(np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros((0, 4)), np.zeros((0, 4, 4)))


def predict(x: NDArray[np.float64], p: NDArray[np.float64], dt_s: NDArray[np.float64],
            accel_psd_m2ps3: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Every track carried ``dt_s`` (M,) ahead under constant velocity: ``(F x, F P Fᵀ + Q)``.

    The two off-diagonal blocks share their terms (``dt P_vv`` and ``q dt²/2``), each computed once: numpy's
    per-call cost, not the arithmetic, is what a dozen tracks cost.
    """
    dt = np.asarray(dt_s, dtype=float)[:, None]
    x_new = x.copy()
    x_new[:, :2] += dt * x[:, 2:]
    d = dt[:, :, None]
    pp, pv, vp, vv = p[:, :2, :2], p[:, :2, 2:], p[:, 2:, :2], p[:, 2:, 2:]
    eye = _EYE2
    q = accel_psd_m2ps3
    p_new = np.empty_like(p)
    p_new[:, :2, :2] = pp + d * (pv + vp) + d * d * vv + q * d ** 3 / 3.0 * eye
    d_vv = d * vv
    cross = q * d ** 2 / 2.0 * eye
    p_new[:, :2, 2:] = pv + d_vv + cross
    p_new[:, 2:, :2] = vp + d_vv + cross
    p_new[:, 2:, 2:] = vv + q * d * eye
    return x_new, p_new


def position_std_m(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """The larger horizontal position standard deviation of each track [m]."""
    return np.sqrt(np.maximum(p[:, 0, 0], p[:, 1, 1]))


def _newest_per_sender(states: Sequence[NeighbourState]) -> dict[int, NeighbourState]:
    """Each sender's measurement with the newest time stamp (the first given of equal ones)."""
    newest: dict[int, NeighbourState] = {}
    for m in states:
        current = newest.get(m.sender_id)
        if current is None or m.t_s > current.t_s:
            newest[m.sender_id] = m
    return newest


def _as_arrays(states: Sequence[NeighbourState]) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    """Ids (K,), time stamps (K,) and measured states (K, 4) of ``states``."""
    ids = np.array([m.sender_id for m in states], dtype=np.int64)
    t_s = np.array([m.t_s for m in states], dtype=float)
    z = np.array([(*m.position_en_m, *m.velocity_en_mps) for m in states], dtype=float).reshape(-1, 4)
    return ids, t_s, z


def update(bank: TrackBank, states: Sequence[NeighbourState], noise: FilterNoise) -> TrackBank:
    """The bank after the measurements ``states`` (each sender's newest only; any not newer than its track is
    ignored: a relayed copy of what was already heard, or a reordered message). New senders start a track.

    Which measurement goes to which track is decided on Python objects (a dozen senders: a dict is cheaper than
    sorting arrays); the filter's arithmetic then runs on arrays in id order, as many rows as fresh measurements.
    """
    if not states:
        return bank
    newest = _newest_per_sender(states)
    slot_of = {vid: i for i, vid in enumerate(bank.ids.tolist())}
    track_times = bank.t_s.tolist()
    fresh_slots: list[int] = []
    fresh: list[NeighbourState] = []
    new: list[NeighbourState] = []
    for vid in sorted(newest):
        m = newest[vid]
        slot = slot_of.get(vid)
        if slot is None:
            new.append(m)
        elif m.t_s > track_times[slot]:
            fresh_slots.append(slot)
            fresh.append(m)
    r = noise.measurement_variance
    x, p, track_t = bank.x.copy(), bank.p.copy(), bank.t_s.copy()
    if fresh:
        k_slot = np.array(fresh_slots, dtype=np.intp)
        _, t_fresh, z_fresh = _as_arrays(fresh)
        xp, pp = predict(x[k_slot], p[k_slot], t_fresh - track_t[k_slot], noise.accel_psd_m2ps3)
        s = pp + np.diag(r)[None]
        gain = np.linalg.solve(s, pp).transpose(0, 2, 1)  # P Sᵀ⁻¹ with P, S symmetric: K = P S⁻¹
        innovation = z_fresh - xp
        x[k_slot] = xp + np.einsum("mij,mj->mi", gain, innovation)
        p_upd = pp - gain @ pp
        p[k_slot] = 0.5 * (p_upd + p_upd.transpose(0, 2, 1))
        track_t[k_slot] = t_fresh
    if not new:
        return TrackBank(bank.ids, track_t, x, p)
    new_ids, new_t, new_z = _as_arrays(new)
    all_ids = np.concatenate([bank.ids, new_ids])
    all_t = np.concatenate([track_t, new_t])
    all_x = np.concatenate([x, new_z])
    all_p = np.concatenate([p, np.broadcast_to(np.diag(r), (len(new), 4, 4))])
    order = np.argsort(all_ids, kind="stable")
    return TrackBank(all_ids[order], all_t[order], all_x[order], all_p[order])


def at_time(bank: TrackBank, t_s: float, noise: FilterNoise) -> tuple[TrackBank, NDArray[np.float64], NDArray[np.float64]]:
    """The tracks still within the bound at ``t_s`` (the bank without the others), and their estimates predicted
    to ``t_s``: state (M', 4) and covariance (M', 4, 4). A track time after ``t_s`` (a clock a little ahead) is not
    predicted backwards."""
    if not len(bank):
        return bank, np.zeros((0, 4)), np.zeros((0, 4, 4))
    x, p = predict(bank.x, bank.p, np.maximum(0.0, t_s - bank.t_s), noise.accel_psd_m2ps3)
    keep = position_std_m(p) <= noise.position_bound_m
    if keep.all():
        return bank, x, p
    kept = TrackBank(bank.ids[keep], bank.t_s[keep], bank.x[keep], bank.p[keep])
    return kept, x[keep], p[keep]


def without(bank: TrackBank, vehicle_ids: frozenset[int]) -> TrackBank:
    """The bank without the tracks of ``vehicle_ids`` (departed neighbours)."""
    if not vehicle_ids or not len(bank):
        return bank
    keep = ~np.isin(bank.ids, np.fromiter(vehicle_ids, dtype=np.int64, count=len(vehicle_ids)))
    if keep.all():
        return bank
    return TrackBank(bank.ids[keep], bank.t_s[keep], bank.x[keep], bank.p[keep])
