"""Effort (SPEC §5): how far each vehicle flew, how fast, and how often it climbed (Algorithm 1).

Algorithm 1 climbs when the camera sees only land or only water. The engine counts those decisions
(``MissionRecord.climb_events``); from ground truth a climb event is an upward crossing of the vehicle's nominal
altitude (its median altitude while alive) plus ``climb_threshold_m``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def path_lengths_m(positions_enu_m: ArrayLike, alive: ArrayLike) -> NDArray[np.float64]:
    """3-D path length [m] of each vehicle over the steps where it was alive at both ends: (T, N, 3) -> (N,)."""
    pos = np.asarray(positions_enu_m, dtype=float)
    a = np.asarray(alive, dtype=bool)
    if pos.shape[0] < 2:
        return np.zeros(pos.shape[1] if pos.ndim == 3 else 0)
    steps = np.linalg.norm(np.diff(pos, axis=0), axis=-1)
    both = a[1:] & a[:-1] & np.isfinite(steps)
    return np.where(both, steps, 0.0).sum(axis=0)


def speeds_mps(t_s: ArrayLike, positions_enu_m: ArrayLike, alive: ArrayLike) -> NDArray[np.float64]:
    """Horizontal ground speed [m/s] between consecutive samples, (T-1, N); NaN where not alive at both ends."""
    t = np.asarray(t_s, dtype=float)
    pos = np.asarray(positions_enu_m, dtype=float)
    a = np.asarray(alive, dtype=bool)
    if len(t) < 2:
        return np.zeros((0, pos.shape[1] if pos.ndim == 3 else 0))
    dt = np.diff(t)[:, None]
    v = np.linalg.norm(np.diff(pos[..., :2], axis=0), axis=-1) / np.where(dt > 0, dt, np.nan)
    return np.where(a[1:] & a[:-1], v, np.nan)


def climb_events_from_altitude(altitude_m: ArrayLike, alive: ArrayLike, climb_threshold_m: float = 1.0) -> NDArray[np.int_]:
    """Upward crossings of (median altitude + threshold) per vehicle, from a (T, N) altitude series."""
    alt = np.asarray(altitude_m, dtype=float)
    a = np.asarray(alive, dtype=bool) & np.isfinite(alt)
    counts = np.zeros(alt.shape[1] if alt.ndim == 2 else 0, dtype=int)
    for i in range(len(counts)):
        h = alt[a[:, i], i]
        if len(h) < 2:
            continue
        above = h > np.median(h) + climb_threshold_m
        counts[i] = int(np.count_nonzero(above[1:] & ~above[:-1]) + (1 if above[0] else 0))
    return counts
