"""Safety (SPEC §5): the minimum 3-D distance between any two flying vehicles, and near misses (< 1 m).

Only vehicles alive at a sample take part (a lost vehicle may fall through the others' altitude band in the
simulator; it is no longer part of the swarm). Pairwise distances are computed in time chunks so that a
200-vehicle record stays within a few tens of megabytes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray


@dataclass(frozen=True)
class SafetyStats:
    """``min_distance_series_m[k]``: closest pair at sample k (NaN with < 2 vehicles alive).

    ``near_miss_pairs``: distinct vehicle pairs (index pairs) that were ever closer than the threshold;
    ``near_miss_events``: times any pair went from >= threshold to < threshold (first sample counts).
    """

    min_distance_m: float
    min_distance_series_m: NDArray[np.float64]
    closest_pair: tuple[int, int] | None
    near_miss_pairs: list[tuple[int, int]]
    near_miss_events: int


def pairwise_safety(
    positions_enu_m: ArrayLike, alive: ArrayLike, near_miss_m: float = 1.0, chunk_elements: int = 4_000_000
) -> SafetyStats:
    """Safety statistics of (T, N, 3) positions with a (T, N) alive mask."""
    pos = np.asarray(positions_enu_m, dtype=float)
    ok = np.asarray(alive, dtype=bool) & np.all(np.isfinite(pos), axis=-1)
    n_t, n = pos.shape[0], pos.shape[1] if pos.ndim == 3 else 0
    series = np.full(n_t, np.nan)
    if n < 2 or n_t == 0:
        return SafetyStats(math.nan, series, None, [], 0)
    iu, ju = np.triu_indices(n, k=1)
    ever = np.zeros(len(iu), bool)
    previous = np.zeros(len(iu), bool)
    events = 0
    best = math.inf
    best_pair: tuple[int, int] | None = None
    step = max(1, chunk_elements // len(iu))
    for lo in range(0, n_t, step):
        p = pos[lo : lo + step]
        a = ok[lo : lo + step]
        diff = p[:, iu, :] - p[:, ju, :]
        d2 = np.einsum("tpc,tpc->tp", diff, diff)
        d2[~(a[:, iu] & a[:, ju])] = np.inf
        mins = np.sqrt(d2.min(axis=1))
        series[lo : lo + step] = np.where(np.isfinite(mins), mins, np.nan)
        k = int(np.argmin(mins))
        if mins[k] < best:
            best = float(mins[k])
            m = int(np.argmin(d2[k]))
            best_pair = (int(iu[m]), int(ju[m]))
        close = d2 < near_miss_m * near_miss_m
        ever |= close.any(axis=0)
        rising = close & ~np.vstack([previous[None, :], close[:-1]])
        events += int(rising.sum())
        previous = close[-1]
    pairs = [(int(i), int(j)) for i, j in zip(iu[ever], ju[ever])]
    return SafetyStats(best if math.isfinite(best) else math.nan, series, best_pair, pairs, events)
