"""Spacing of the boundary drones along the true edge (SPEC §5): arc gaps, their CV and the largest gap.

Each drone is projected onto the true boundary ring; the arc-length gaps between consecutive projections (cyclic)
are what the β separation of eqs (6-7) and the encircling speed u_c try to even out. CV = std/mean of the gaps
(0 for a perfect ring); ``max_gap_ratio`` = largest gap ÷ ideal gap (perimeter / n; 1 for a perfect ring).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gcs.polygon.ring import project_onto_ring


@dataclass(frozen=True)
class SpacingStats:
    """Arc gaps [m] between consecutive drones along the edge, with CV and max gap ÷ ideal gap."""

    gaps_m: NDArray[np.float64]
    cv: float
    max_gap_ratio: float


def spacing_from_arcs(arc_m: ArrayLike, perimeter_m: float) -> SpacingStats:
    """Spacing statistics from the drones' arc positions [m] on a closed edge of length ``perimeter_m``."""
    arcs = np.sort(np.mod(np.asarray(arc_m, dtype=float).ravel(), perimeter_m)) if perimeter_m > 0 else np.zeros(0)
    arcs = arcs[np.isfinite(arcs)]
    if len(arcs) < 2:
        return SpacingStats(np.zeros(0), math.nan, math.nan)
    gaps = np.diff(np.concatenate([arcs, [arcs[0] + perimeter_m]]))
    ideal = perimeter_m / len(arcs)
    return SpacingStats(gaps, float(np.std(gaps) / ideal), float(gaps.max() / ideal))


def spacing_on_edge(boundary_positions_en_m: ArrayLike, flood_ring_en_m: ArrayLike) -> SpacingStats:
    """Project the (n, 2|3) boundary drones onto the (K, 2) true edge ring and measure their arc gaps."""
    pts = np.asarray(boundary_positions_en_m, dtype=float)
    proj = project_onto_ring(pts.reshape(-1, pts.shape[-1])[:, :2], flood_ring_en_m)
    return spacing_from_arcs(proj.arc_m, proj.perimeter_m)
