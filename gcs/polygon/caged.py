"""The ground station's caged polygon: the boundary drones' ring fused with the edge points their cameras see.

Paper §III-A: connecting the boundary drones forms a polygon that cages the flood. Eight vertices on a 16 m circle
cover only ~0.90 of its area (octagon / circle = 2√2/π), so the ground station also uses what each boundary
camera sees: the water/land boundary pixels of its footprint, georeferenced in the mission ENU frame
(``PerceptionResult.edge_points_en_m`` + the drone's position). With ~11.5 m footprints the cameras see most of
the edge, and the fused ring reaches IoU ≈ 0.99 on the paper's circle.

Method (pure numpy, deterministic):

1. Anchor per drone: the median of its own edge points (≥ 3 points), else its reported position. Anchors in
   ring order make a reference ring (made counter-clockwise; if the given order makes it self-intersect, the
   anchors are re-ordered by angle round their median, which is right for any star-shaped flood). Drones with non-finite positions and no edge points
   are simply missing: the ring closes over the gap.
2. Every edge point (and the anchor of a drone that sees no edge) is projected onto the reference ring, giving an
   arc position and a signed offset across it.
3. Outliers are points whose offset differs from the median offset of their arc neighbourhood (±``window_m``)
   by more than ``max(outlier_tolerance_m, mad_factor · 1.4826 · MAD)``: stray boundary pixels from perception
   noise, a drone whose position is wrong while its camera is right, etc.
4. The surviving points are binned along the arc (``bin_length_m``); each bin gives one vertex, the
   coordinate-wise median of its points. Drone positions are only used in bins where no camera saw the edge.
5. The ring is made a valid simple polygon (largest part if it self-intersects) and returned counter-clockwise.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from shapely.geometry import MultiPoint, Polygon

from gcs.polygon.ring import orient_ccw, project_onto_ring, signed_area_m2

_MIN_ANCHOR_POINTS = 3


def caged_polygon(
    drone_positions_en_m: ArrayLike,
    edge_points_en_m: Sequence[ArrayLike],
    *,
    bin_length_m: float = 0.5,
    window_m: float = 3.0,
    outlier_tolerance_m: float = 1.0,
    mad_factor: float = 3.0,
) -> NDArray[np.float64]:
    """Fuse boundary drones (N, 2) in ring order with their cameras' edge points into a (K, 2) CCW ring.

    ``edge_points_en_m[i]`` holds the absolute ENU edge points drone ``i`` sees ((K_i, 2), may be empty); the list
    may be shorter than N (missing entries mean "no points"). Rows of ``drone_positions_en_m`` with NaN mark
    drones that did not report. Returns an empty (0, 2) array when fewer than three usable points exist.
    """
    drones = np.asarray(drone_positions_en_m, dtype=float).reshape(-1, 2)
    per_drone = [_finite_points(edge_points_en_m[i]) if i < len(edge_points_en_m) else np.zeros((0, 2)) for i in range(len(drones))]
    extra = [_finite_points(p) for p in edge_points_en_m[len(drones) :]]

    anchors: list[NDArray[np.float64]] = []
    for position, points in zip(drones, per_drone):
        if len(points) >= _MIN_ANCHOR_POINTS:
            anchors.append(np.median(points, axis=0))
        elif np.all(np.isfinite(position)):
            anchors.append(position)
    edge = np.concatenate(per_drone + extra) if (per_drone or extra) else np.zeros((0, 2))
    drone_only = _positions_without_edge(drones, per_drone)

    reference = _reference_ring(np.array(anchors).reshape(-1, 2), edge, drone_only)
    if reference is None:
        return np.zeros((0, 2))

    points = np.concatenate([edge, drone_only])
    is_edge = np.concatenate([np.ones(len(edge), bool), np.zeros(len(drone_only), bool)])
    if len(points) < 3:
        return np.zeros((0, 2))
    proj = project_onto_ring(points, reference)
    perimeter = proj.perimeter_m
    if perimeter <= 0.0:
        return np.zeros((0, 2))

    n_bins = max(8, int(np.ceil(perimeter / bin_length_m)))
    bin_of = np.minimum((proj.arc_m / perimeter * n_bins).astype(int), n_bins - 1)
    keep = _inliers(bin_of, proj.offset_m, n_bins, perimeter, window_m, outlier_tolerance_m, mad_factor)

    edge_bins = np.zeros(n_bins, bool)
    edge_bins[bin_of[keep & is_edge]] = True
    keep &= is_edge | ~edge_bins[bin_of]

    vertices = _bin_medians(points[keep], bin_of[keep], proj.arc_m[keep])
    return _valid_ccw_ring(vertices)


def _finite_points(points: ArrayLike) -> NDArray[np.float64]:
    arr = np.asarray(points, dtype=float).reshape(-1, 2)
    return arr[np.all(np.isfinite(arr), axis=1)]


def _positions_without_edge(drones: NDArray[np.float64], per_drone: list[NDArray[np.float64]]) -> NDArray[np.float64]:
    """Positions of the drones whose cameras gave too few edge points to stand for themselves."""
    rows = [p for p, pts in zip(drones, per_drone) if len(pts) < _MIN_ANCHOR_POINTS and np.all(np.isfinite(p))]
    return np.array(rows).reshape(-1, 2)


def _reference_ring(
    anchors: NDArray[np.float64], edge: NDArray[np.float64], drone_only: NDArray[np.float64]
) -> NDArray[np.float64] | None:
    """The anchors in ring order (CCW), or the convex hull of all points when the anchors do not span an area."""
    if len(anchors) >= 3 and abs(signed_area_m2(anchors)) > 1e-6:
        if not Polygon(anchors).is_valid:
            centre = np.median(anchors, axis=0)
            anchors = anchors[np.argsort(np.arctan2(anchors[:, 1] - centre[1], anchors[:, 0] - centre[0]))]
        return orient_ccw(anchors)
    cloud = np.concatenate([edge, drone_only, anchors])
    if len(cloud) < 3:
        return None
    hull = MultiPoint([tuple(p) for p in cloud]).convex_hull
    if not isinstance(hull, Polygon) or hull.area <= 1e-6:
        return None
    return orient_ccw(np.asarray(hull.exterior.coords)[:-1])


def _inliers(
    bin_of: NDArray[np.int_],
    offset_m: NDArray[np.float64],
    n_bins: int,
    perimeter_m: float,
    window_m: float,
    tolerance_m: float,
    mad_factor: float,
) -> NDArray[np.bool_]:
    """Points whose offset agrees with the robust (median/MAD) offset of their arc neighbourhood."""
    half = max(1, int(round(window_m / (perimeter_m / n_bins))))
    order = np.argsort(bin_of, kind="stable")
    sorted_bins = bin_of[order]
    starts = np.searchsorted(sorted_bins, np.arange(n_bins), side="left")
    ends = np.searchsorted(sorted_bins, np.arange(n_bins), side="right")
    occupied = np.flatnonzero(ends > starts)
    keep = np.ones(len(offset_m), bool)
    sorted_offsets = offset_m[order]
    for b in occupied:
        neighbourhood = [(b + k) % n_bins for k in range(-half, half + 1)] if 2 * half + 1 < n_bins else range(n_bins)
        values = np.concatenate([sorted_offsets[starts[j] : ends[j]] for j in neighbourhood])
        med = float(np.median(values))
        mad = float(np.median(np.abs(values - med)))
        limit = max(tolerance_m, mad_factor * 1.4826 * mad)
        members = order[starts[b] : ends[b]]
        keep[members] = np.abs(offset_m[members] - med) <= limit
    return keep


def _bin_medians(points: NDArray[np.float64], bin_of: NDArray[np.int_], arc_m: NDArray[np.float64]) -> NDArray[np.float64]:
    """One vertex per occupied bin (coordinate-wise median of its points), in arc order."""
    if len(points) == 0:
        return np.zeros((0, 2))
    order = np.lexsort((arc_m, bin_of))
    bins_sorted = bin_of[order]
    cuts = np.flatnonzero(np.diff(bins_sorted)) + 1
    groups = np.split(order, cuts)
    return np.array([np.median(points[g], axis=0) for g in groups])


def _valid_ccw_ring(vertices: NDArray[np.float64]) -> NDArray[np.float64]:
    """A simple CCW ring from the vertices (largest piece when the vertex order self-intersects)."""
    if len(vertices) < 3:
        return np.zeros((0, 2))
    poly = Polygon(vertices)
    if not poly.is_valid:
        fixed = shapely.make_valid(poly)
        parts = [g for g in getattr(fixed, "geoms", [fixed]) if isinstance(g, Polygon) and g.area > 0.0]
        if not parts:
            return np.zeros((0, 2))
        poly = max(parts, key=lambda g: g.area)
    if poly.area <= 0.0:
        return np.zeros((0, 2))
    ring = np.asarray(poly.exterior.coords)[:-1]
    return orient_ccw(ring)
