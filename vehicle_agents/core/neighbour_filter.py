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


EMPTY_BANK = TrackBank(np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros((0, 4)), np.zeros((0, 4, 4)))


def predict(x: NDArray[np.float64], p: NDArray[np.float64], dt_s: NDArray[np.float64],
            accel_psd_m2ps3: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Every track carried ``dt_s`` (M,) ahead under constant velocity: ``(F x, F P Fᵀ + Q)``."""
    dt = np.asarray(dt_s, dtype=float)[:, None]
    x_new = x.copy()
    x_new[:, :2] += dt * x[:, 2:]
    d = dt[:, :, None]
    pp, pv, vp, vv = p[:, :2, :2], p[:, :2, 2:], p[:, 2:, :2], p[:, 2:, 2:]
    eye = np.eye(2)[None]
    q = accel_psd_m2ps3
    p_new = np.empty_like(p)
    p_new[:, :2, :2] = pp + d * (pv + vp) + d * d * vv + q * d ** 3 / 3.0 * eye
    p_new[:, :2, 2:] = pv + d * vv + q * d ** 2 / 2.0 * eye
    p_new[:, 2:, :2] = vp + d * vv + q * d ** 2 / 2.0 * eye
    p_new[:, 2:, 2:] = vv + q * d * eye
    return x_new, p_new


def position_std_m(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """The larger horizontal position standard deviation of each track [m]."""
    return np.sqrt(np.maximum(p[:, 0, 0], p[:, 1, 1]))


def _measurements(states: Sequence[NeighbourState]) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    ids = np.fromiter((m.sender_id for m in states), dtype=np.int64, count=len(states))
    t_s = np.fromiter((m.t_s for m in states), dtype=float, count=len(states))
    z = np.array([(*m.position_en_m, *m.velocity_en_mps) for m in states], dtype=float).reshape(-1, 4)
    return ids, t_s, z


def update(bank: TrackBank, states: Sequence[NeighbourState], noise: FilterNoise) -> TrackBank:
    """The bank after the measurements ``states`` (each sender's newest only; any not newer than its track is
    ignored: a relayed copy of what was already heard, or a reordered message). New senders start a track."""
    if not states:
        return bank
    ids, t_s, z = _measurements(states)
    order = np.lexsort((-t_s, ids))
    ids, t_s, z = ids[order], t_s[order], z[order]
    first = np.ones(ids.size, dtype=bool)
    first[1:] = ids[1:] != ids[:-1]
    ids, t_s, z = ids[first], t_s[first], z[first]
    r = noise.measurement_variance
    slot = np.searchsorted(bank.ids, ids)
    slot_clipped = np.minimum(slot, max(len(bank) - 1, 0))
    known = (slot < len(bank)) & (bank.ids[slot_clipped] == ids) if len(bank) else np.zeros(ids.size, dtype=bool)
    x, p, track_t = bank.x.copy(), bank.p.copy(), bank.t_s.copy()
    fresh = known & (t_s > track_t[slot_clipped]) if len(bank) else known
    if np.any(fresh):
        k_slot = slot[fresh]
        xp, pp = predict(x[k_slot], p[k_slot], t_s[fresh] - track_t[k_slot], noise.accel_psd_m2ps3)
        s = pp + np.diag(r)[None]
        gain = np.linalg.solve(s, pp).transpose(0, 2, 1)  # P Sᵀ⁻¹ with P, S symmetric: K = P S⁻¹
        innovation = z[fresh] - xp
        x[k_slot] = xp + np.einsum("mij,mj->mi", gain, innovation)
        p_upd = pp - gain @ pp
        p[k_slot] = 0.5 * (p_upd + p_upd.transpose(0, 2, 1))
        track_t[k_slot] = t_s[fresh]
    new = ~known
    if not np.any(new):
        return TrackBank(bank.ids, track_t, x, p)
    all_ids = np.concatenate([bank.ids, ids[new]])
    all_t = np.concatenate([track_t, t_s[new]])
    all_x = np.concatenate([x, z[new]])
    all_p = np.concatenate([p, np.broadcast_to(np.diag(r), (int(np.count_nonzero(new)), 4, 4))])
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
