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
from shapely.geometry import Polygon

from gcs.polygon.ring import densify_ring, distance_to_ring_m, open_ring, ring_perimeter_m


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


def hausdorff_m(ring_a_en_m: ArrayLike, ring_b_en_m: ArrayLike, max_segment_m: float = 0.25, max_points: int = 1000) -> float:
    """Symmetric Hausdorff distance [m] between two closed rings; NaN if either has fewer than 3 vertices.

    Each ring is densified to ``max_segment_m`` but to no more than ~``max_points`` vertices (big floods), so the
    result may under-read by at most half the spacing used.
    """
    a, b = open_ring(ring_a_en_m), open_ring(ring_b_en_m)
    if len(a) < 3 or len(b) < 3:
        return math.nan
    spacing = max(max_segment_m, ring_perimeter_m(a) / max_points, ring_perimeter_m(b) / max_points)
    a_dense, b_dense = densify_ring(a, spacing), densify_ring(b, spacing)
    return float(max(np.max(distance_to_ring_m(a_dense, b)), np.max(distance_to_ring_m(b_dense, a))))
