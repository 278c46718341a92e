"""Plane geometry every package shares: a polygon ring's area and centroid (shoelace), and the ground footprint of
a downward camera (SPEC §3). Written once here so that the ground station, the agents, the simulator and the
messages measure the same polygon the same way.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray


def open_ring(ring_en_m: ArrayLike) -> NDArray[np.float64]:
    """A (K, 2) ring without the closing vertex that repeats the first one."""
    ring = np.asarray(ring_en_m, dtype=float).reshape(-1, 2)
    if len(ring) > 1 and np.array_equal(ring[0], ring[-1]):
        ring = ring[:-1]
    return ring


def ring_area_centroid(ring_en_m: ArrayLike) -> tuple[float, NDArray[np.float64]]:
    """Signed area [m²] (positive counter-clockwise, east right and north up) and area centroid [m] of a ring;
    a degenerate ring (fewer than 3 vertices or no area) gives area 0 and the vertices' mean."""
    ring = open_ring(ring_en_m)
    if len(ring) == 0:
        return 0.0, np.full(2, np.nan)
    if len(ring) < 3:
        return 0.0, ring.mean(axis=0)
    x, y = ring[:, 0], ring[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * float(cross.sum())
    if abs(area) < 1e-12:
        return 0.0, ring.mean(axis=0)
    cx = float(((x + xn) * cross).sum()) / (6.0 * area)
    cy = float(((y + yn) * cross).sum()) / (6.0 * area)
    return area, np.array([cx, cy])


def signed_area_m2(ring_en_m: ArrayLike) -> float:
    """Shoelace area [m²]: positive for a counter-clockwise ring."""
    return ring_area_centroid(ring_en_m)[0]


def footprint_side_m(altitude_m: ArrayLike, fov_deg: float) -> NDArray[np.float64]:
    """Ground side [m] of a square downward camera's image: 2 h tan(fov/2); 0 at or below the ground."""
    h = np.asarray(altitude_m, dtype=float)
    return np.where(h > 0.0, 2.0 * h * math.tan(math.radians(fov_deg) / 2.0), 0.0)
