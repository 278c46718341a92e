"""Encircle time T_enc (SPEC §5): when the boundary ring closes round the flood.

The engine knows the paper's event (the two groups' leading drones meet; ``MissionRecord.encircle_time_s``). From
ground truth alone we read the same event off the spacing: before the groups meet, the far side of the flood is an
open gap several times the ideal one; the ring counts as closed at the first sample where the largest arc gap
falls to ``threshold`` × ideal (1.5 by default, i.e. the leading drones are within 1.5 ideal gaps of each other).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike


def ring_closed_time_s(t_s: ArrayLike, max_gap_ratio: ArrayLike, threshold: float = 1.5) -> float:
    """First time [s] at which the largest gap ÷ ideal gap is at most ``threshold``; NaN if it never is."""
    t = np.asarray(t_s, dtype=float)
    ratio = np.asarray(max_gap_ratio, dtype=float)
    hit = np.flatnonzero(np.isfinite(ratio) & (ratio <= threshold))
    return float(t[hit[0]]) if len(hit) else math.nan


def encircle_speed_floor_s(perimeter_m: float, speed_mps: float) -> float:
    """Lower bound on T_enc [s]: each group covers half the perimeter at ``speed_mps`` (SPEC §5)."""
    return 0.5 * perimeter_m / speed_mps if speed_mps > 0 else math.inf
