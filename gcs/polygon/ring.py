"""Plain geometry of closed rings in the mission ENU plane: area, perimeter, orientation, projection.

A ring is a (K, 2) array of (east, north) metres, NOT closed (the last vertex is not a copy of the first), the
convention of ``FloodModel.boundary_en_m`` and ``PolygonSample``. Everything here is vectorised numpy; the caged
polygon and the metrics (tracking error, spacing, Hausdorff) all measure against rings through these functions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray


def open_ring(ring_en_m: ArrayLike) -> NDArray[np.float64]:
    """The ring as a float (K, 2) array without a repeated closing vertex."""
    ring = np.asarray(ring_en_m, dtype=float).reshape(-1, 2)
    if len(ring) > 1 and np.array_equal(ring[0], ring[-1]):
        ring = ring[:-1]
    return ring


def signed_area_m2(ring_en_m: ArrayLike) -> float:
    """Shoelace area [m²]: positive for a counter-clockwise ring (east right, north up)."""
    ring = open_ring(ring_en_m)
    if len(ring) < 3:
        return 0.0
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


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


def project_onto_ring(points_en_m: ArrayLike, ring_en_m: ArrayLike, chunk_elements: int = 2_000_000) -> RingProjection:
    """Project (P, 2) points onto the closed ring (K, 2): nearest point, distance, arc position, signed offset.

    Brute force over all segments (P x K), chunked over points so memory stays bounded for big fleets.
    """
    pts = np.asarray(points_en_m, dtype=float).reshape(-1, 2)
    ring = open_ring(ring_en_m)
    n_pts = len(pts)
    if len(ring) == 0 or n_pts == 0:
        empty = np.full(n_pts, np.nan)
        return RingProjection(empty, empty.copy(), empty.copy(), np.full((n_pts, 2), np.nan), 0.0)
    start = ring
    seg = np.roll(ring, -1, axis=0) - ring
    seg_len = np.linalg.norm(seg, axis=1)
    seg_len2 = np.where(seg_len > 0.0, seg_len**2, 1.0)
    cum = np.concatenate([[0.0], np.cumsum(seg_len)[:-1]])
    perimeter = float(seg_len.sum())
    distance = np.empty(n_pts)
    arc = np.empty(n_pts)
    offset = np.empty(n_pts)
    nearest = np.empty((n_pts, 2))
    step = max(1, chunk_elements // max(1, len(ring)))
    for lo in range(0, n_pts, step):
        p = pts[lo : lo + step]
        rel = p[:, None, :] - start[None, :, :]
        u = np.clip(np.einsum("pkc,kc->pk", rel, seg) / seg_len2[None, :], 0.0, 1.0)
        foot = start[None, :, :] + u[..., None] * seg[None, :, :]
        d2 = np.sum((p[:, None, :] - foot) ** 2, axis=-1)
        k = np.argmin(d2, axis=1)
        rows = np.arange(len(p))
        distance[lo : lo + step] = np.sqrt(d2[rows, k])
        arc[lo : lo + step] = cum[k] + u[rows, k] * seg_len[k]
        nearest[lo : lo + step] = foot[rows, k]
        cross = seg[k, 0] * rel[rows, k, 1] - seg[k, 1] * rel[rows, k, 0]
        offset[lo : lo + step] = -np.sign(cross) * distance[lo : lo + step]
    if perimeter > 0.0:
        arc = np.mod(arc, perimeter)
    return RingProjection(distance, arc, offset, nearest, perimeter)


def distance_to_ring_m(points_en_m: ArrayLike, ring_en_m: ArrayLike) -> NDArray[np.float64]:
    """Unsigned distance [m] of each point to the closed ring."""
    return project_onto_ring(points_en_m, ring_en_m).distance_m
