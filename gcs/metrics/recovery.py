"""Recovery after a loss (SPEC §5, §7): how long the remaining boundary drones take to re-space.

A loss is a vehicle whose ``alive`` flag goes from True to False. The recovery time is the time from the loss
until the spacing CV is below ``threshold`` (0.1) and stays there for ``hold_s`` (or until the record ends), so a
single lucky sample while the ring is still reshuffling does not count.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike


@dataclass(frozen=True)
class LossEvent:
    """Vehicle ``index`` (column of the record) was lost at ``t_s``."""

    index: int
    t_s: float


def vehicle_losses(t_s: ArrayLike, alive: ArrayLike) -> list[LossEvent]:
    """Every True→False transition of the (T, N) alive mask, in time order."""
    t = np.asarray(t_s, dtype=float)
    a = np.asarray(alive, dtype=bool)
    if a.ndim != 2 or a.shape[0] < 2:
        return []
    k, i = np.nonzero(a[:-1] & ~a[1:])
    order = np.lexsort((i, k))
    return [LossEvent(int(i[o]), float(t[k[o] + 1])) for o in order]


def recovery_time_s(t_s: ArrayLike, spacing_cv: ArrayLike, t_loss_s: float, threshold: float = 0.1, hold_s: float = 1.0) -> float:
    """Seconds from ``t_loss_s`` until the CV is under ``threshold`` for ``hold_s``; NaN if it never recovers."""
    t = np.asarray(t_s, dtype=float)
    cv = np.asarray(spacing_cv, dtype=float)
    after = t >= t_loss_s
    good = after & np.isfinite(cv) & (cv < threshold)
    idx = np.flatnonzero(after)
    if len(idx) == 0:
        return math.nan
    for k in idx:
        if not good[k]:
            continue
        window = (t >= t[k]) & (t <= t[k] + hold_s)
        if np.all(good[window]):
            return float(t[k] - t_loss_s)
    return math.nan
