"""The map's alerts that are about geometry (pure): a ring gap wider than 1.5× the ideal, and stretches of the caged
polygon's edge under no camera footprint.

The ideal gap is the caged polygon's perimeter shared equally by the boundary drones still flying (the spacing the
ring's consensus drives towards, paper §III-A). An edge stretch under no footprint is a part of the polygon that no
camera sees now: the polygon there is drawn between the edge points on either side, not observed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from shapely.geometry import LineString, MultiLineString, box
from shapely.ops import unary_union

from gcs.polygon.ring import open_ring

GAP_FACTOR = 1.5


@dataclass(frozen=True)
class RingGap:
    """Two ring neighbours (ids in ring order) further apart than ``GAP_FACTOR`` × the ideal gap."""

    vehicle_a: int
    vehicle_b: int
    gap_m: float
    ideal_m: float


def ring_gaps(ring_ids: list[int], positions_en_m: ArrayLike, perimeter_m: float,
              factor: float = GAP_FACTOR) -> list[RingGap]:
    """Gaps between consecutive flying boundary drones (cyclic, ring order; NaN rows are drones not flying) wider
    than ``factor`` × ``perimeter_m`` / (drones flying). Fewer than three flying drones: no ring, no gaps."""
    p = np.asarray(positions_en_m, dtype=float).reshape(-1, 2)
    flying = [i for i in range(len(ring_ids)) if np.all(np.isfinite(p[i]))]
    if len(flying) < 3 or not perimeter_m > 0.0:
        return []
    ideal_m = perimeter_m / len(flying)
    gaps = []
    for k, i in enumerate(flying):
        j = flying[(k + 1) % len(flying)]
        gap_m = float(np.hypot(*(p[j] - p[i])))
        if gap_m > factor * ideal_m:
            gaps.append(RingGap(ring_ids[i], ring_ids[j], gap_m, ideal_m))
    return gaps


def uncovered_edge_m(ring_en_m: ArrayLike, centres_en_m: ArrayLike, sides_m: ArrayLike) -> list[float]:
    """Lengths [m] of the stretches of the polygon's edge outside every camera footprint (squares of ``sides_m``
    around ``centres_en_m``), longest first; empty when the whole edge is seen or there is no polygon."""
    ring = open_ring(ring_en_m)
    if len(ring) < 3:
        return []
    edge = LineString(np.vstack([ring, ring[:1]]))
    squares = [box(c[0] - s / 2, c[1] - s / 2, c[0] + s / 2, c[1] + s / 2)
               for c, s in zip(np.asarray(centres_en_m, dtype=float).reshape(-1, 2), np.asarray(sides_m, dtype=float))
               if np.all(np.isfinite(c)) and np.isfinite(s) and s > 0.0]
    unseen = edge.difference(unary_union(squares)) if squares else edge
    if unseen.is_empty:
        return []
    parts = list(unseen.geoms) if isinstance(unseen, MultiLineString) else [unseen]
    lengths = _join_across_start([p for p in parts if isinstance(p, LineString)], edge)
    return sorted(lengths, reverse=True)


def _join_across_start(parts: list[LineString], edge: LineString) -> list[float]:
    """Part lengths, with the pieces that meet at the ring's first vertex counted as the one stretch they are."""
    start = edge.coords[0]
    touching = [p for p in parts if p.coords[0] == start or p.coords[-1] == start]
    rest = [p.length for p in parts if p not in touching]
    if touching:
        rest.append(sum(p.length for p in touching))
    return rest

