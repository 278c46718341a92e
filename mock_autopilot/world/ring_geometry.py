"""Area and centroid of a simple polygon ring (shoelace formulas), shared by the shape models."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def ring_area_centroid(ring_en_m: NDArray[np.float64]) -> tuple[float, NDArray[np.float64]]:
    """Signed area [m²] (positive for counter-clockwise) and centroid [m] of a (K, 2) ring, not closed."""
    x, y = ring_en_m[:, 0], ring_en_m[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * float(cross.sum())
    if abs(area) < 1e-12:
        return 0.0, ring_en_m.mean(axis=0)
    cx = float(((x + xn) * cross).sum()) / (6.0 * area)
    cy = float(((y + yn) * cross).sum()) / (6.0 * area)
    return area, np.array([cx, cy])
