"""Boundary tracking error (SPEC §5): how far each boundary drone is from the true flood edge.

The control goal of eq (8) is q_b → p, the edge point under the drone; the error is measured from ground truth as
the horizontal distance from the drone to the true boundary ring.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gcs.polygon.ring import distance_to_ring_m


def tracking_errors_m(boundary_positions_en_m: ArrayLike, flood_ring_en_m: ArrayLike) -> NDArray[np.float64]:
    """Horizontal distance [m] of each (n, 2|3) boundary drone to the (K, 2) true edge ring."""
    pts = np.asarray(boundary_positions_en_m, dtype=float)
    return distance_to_ring_m(pts.reshape(-1, pts.shape[-1])[:, :2], flood_ring_en_m)


def rms_m(errors_m: ArrayLike) -> float:
    """Root mean square of the finite errors; NaN when there are none."""
    e = np.asarray(errors_m, dtype=float).ravel()
    e = e[np.isfinite(e)]
    return float(np.sqrt(np.mean(e**2))) if len(e) else math.nan


def max_m(errors_m: ArrayLike) -> float:
    """Largest finite error; NaN when there are none."""
    e = np.asarray(errors_m, dtype=float).ravel()
    e = e[np.isfinite(e)]
    return float(e.max()) if len(e) else math.nan
