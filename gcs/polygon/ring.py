"""Plain geometry of closed rings in the mission ENU plane: area, perimeter, orientation, projection.

A ring is a (K, 2) array of (east, north) metres, NOT closed (the last vertex is not a copy of the first), the
convention of ``FloodModel.boundary_en_m`` and ``PolygonSample``. Everything here is vectorised numpy; the caged
polygon and the metrics (tracking error, spacing, Hausdorff) all measure against rings through these functions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import LineString, Polygon

from mission_plan.geometry import open_ring, signed_area_m2

__all__ = ["open_ring", "signed_area_m2"]


def ring_area_m2(ring_en_m: ArrayLike) -> float:
    """Enclosed area [m²] of a simple ring, whatever its orientation."""
    return abs(signed_area_m2(ring_en_m))


def ring_perimeter_m(ring_en_m: ArrayLike) -> float:
    """Length [m] of the closed ring, closing edge included."""
    ring = open_ring(ring_en_m)
    if len(ring) < 2:
        return 0.0
    return float(np.sum(np.linalg.norm(np.roll(ring, -1, axis=0) - ring, axis=1)))


def orient_ccw(ring_en_m: ArrayLike) -> NDArray[np.float64]:
    """The ring, reversed if needed so that it runs counter-clockwise (RFC 7946 outer-ring order)."""
    ring = open_ring(ring_en_m)
    return ring[::-1].copy() if signed_area_m2(ring) < 0.0 else ring.copy()


def densify_ring(ring_en_m: ArrayLike, max_segment_m: float) -> NDArray[np.float64]:
    """Insert vertices so that no edge of the closed ring is longer than ``max_segment_m``."""
    ring = open_ring(ring_en_m)
    if len(ring) < 2 or max_segment_m <= 0.0:
        return ring.copy()
    nxt = np.roll(ring, -1, axis=0)
    lengths = np.linalg.norm(nxt - ring, axis=1)
    pieces = np.maximum(1, np.ceil(lengths / max_segment_m).astype(int))
    seg = np.repeat(np.arange(len(ring)), pieces)
    starts = np.cumsum(pieces) - pieces
    frac = (np.arange(int(pieces.sum())) - np.repeat(starts, pieces)) / np.repeat(pieces, pieces)
    return ring[seg] + frac[:, None] * (nxt[seg] - ring[seg])


@dataclass(frozen=True)
class RingProjection:
    """Nearest points on a closed ring for a batch of query points.

    ``distance_m`` is the unsigned distance to the ring, ``arc_m`` the arc length from vertex 0 (in the ring's own
    direction) of the nearest point, ``offset_m`` the signed distance (positive on the right of the direction of
    travel, i.e. outside for a counter-clockwise ring), ``nearest_en_m`` the nearest points themselves.
    """

    distance_m: NDArray[np.float64]
    arc_m: NDArray[np.float64]
    offset_m: NDArray[np.float64]
    nearest_en_m: NDArray[np.float64]
    perimeter_m: float


def project_onto_ring(points_en_m: ArrayLike, ring_en_m: ArrayLike, *, with_nearest: bool = True) -> RingProjection:
    """Project (P, 2) points onto the closed ring (K, 2): nearest point, distance, arc position, signed offset.

    GEOS (through shapely, vectorised over points) finds the nearest point and its arc position; the side is read
    from whether the point lies inside the ring and which way the ring turns (right of travel = outside for CCW).
    ``with_nearest=False`` skips computing the nearest points (NaN) when only distances and arcs are needed.
    """
    pts = np.asarray(points_en_m, dtype=float).reshape(-1, 2)
    ring = open_ring(ring_en_m)
    n_pts = len(pts)
    if len(ring) < 2 or n_pts == 0:
        empty = np.full(n_pts, np.nan)
        return RingProjection(empty, empty.copy(), empty.copy(), np.full((n_pts, 2), np.nan), 0.0)
    line = LineString(np.vstack([ring, ring[:1]]))
    perimeter = float(line.length)
    finite = np.all(np.isfinite(pts), axis=1)
    geoms = shapely.points(np.where(finite[:, None], pts, 0.0))
    distance = np.where(finite, shapely.distance(geoms, line), np.nan)
    arc = np.where(finite, shapely.line_locate_point(line, geoms), np.nan)
    nearest = np.full((n_pts, 2), np.nan)
    if with_nearest:
        nearest = shapely.get_coordinates(shapely.line_interpolate_point(line, np.where(finite, arc, 0.0)))
        nearest[~finite] = np.nan
    if len(ring) >= 3:
        inside = shapely.contains_xy(Polygon(ring), pts[:, 0], pts[:, 1])
        outward = 1.0 if signed_area_m2(ring) >= 0.0 else -1.0
        offset = np.where(inside, -outward, outward) * distance
    else:
        offset = distance.copy()
    if perimeter > 0.0:
        arc = np.mod(arc, perimeter)
    return RingProjection(distance, arc, offset, nearest, perimeter)


def distance_to_ring_m(points_en_m: ArrayLike, ring_en_m: ArrayLike) -> NDArray[np.float64]:
    """Unsigned distance [m] of each point to the closed ring."""
    pts = np.asarray(points_en_m, dtype=float).reshape(-1, 2)
    ring = open_ring(ring_en_m)
    if len(ring) < 2 or len(pts) == 0:
        return np.full(len(pts), np.nan)
    line = LineString(np.vstack([ring, ring[:1]]))
    finite = np.all(np.isfinite(pts), axis=1)
    return np.where(finite, shapely.distance(shapely.points(np.where(finite[:, None], pts, 0.0)), line), np.nan)
