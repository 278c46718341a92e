"""Caged-polygon quality (SPEC §5): intersection over union and Hausdorff distance against the true flood.

The true flood polygon is the model's outer boundary ring (islands, where a model has them, are not part of what
a caging ring can describe). Hausdorff is between the two boundaries, computed on rings densified to
``max_segment_m`` so that long chords of a sparse polygon are measured along their length, not only at vertices.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import ArrayLike
from shapely.geometry import LinearRing, Polygon

from gcs.polygon.ring import densify_ring, open_ring


def _polygon(ring_en_m: ArrayLike) -> Polygon | None:
    ring = open_ring(ring_en_m)
    if len(ring) < 3 or not np.all(np.isfinite(ring)):
        return None
    poly = Polygon(ring)
    if not poly.is_valid:
        poly = shapely.make_valid(poly)
    return poly if poly.area > 0.0 else None


def polygon_iou(ring_a_en_m: ArrayLike, ring_b_en_m: ArrayLike) -> float:
    """Area of intersection ÷ area of union of two rings; 0 when one is empty, NaN when both are."""
    a, b = _polygon(ring_a_en_m), _polygon(ring_b_en_m)
    if a is None and b is None:
        return math.nan
    if a is None or b is None:
        return 0.0
    union = a.union(b).area
    return float(a.intersection(b).area / union) if union > 0 else math.nan


def hausdorff_m(ring_a_en_m: ArrayLike, ring_b_en_m: ArrayLike, max_segment_m: float = 0.25) -> float:
    """Symmetric Hausdorff distance [m] between two closed rings; NaN if either has fewer than 3 vertices."""
    a, b = open_ring(ring_a_en_m), open_ring(ring_b_en_m)
    if len(a) < 3 or len(b) < 3:
        return math.nan
    a_dense, b_dense = densify_ring(a, max_segment_m), densify_ring(b, max_segment_m)
    a_to_b = shapely.distance(shapely.points(a_dense), LinearRing(b))
    b_to_a = shapely.distance(shapely.points(b_dense), LinearRing(a))
    return float(max(np.max(a_to_b), np.max(b_to_a)))
