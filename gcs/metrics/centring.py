"""Leader centring error (SPEC §5): distance from the inner leader to the true flood centroid.

Eq (9) drives the leader to the centroid of the boundary drones; what matters to coverage is the flood's own
centroid, so the metric uses ground truth.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def centring_errors_m(leader_positions_en_m: ArrayLike, flood_centroid_en_m: ArrayLike) -> NDArray[np.float64]:
    """Horizontal distance [m] of each (..., 2|3) leader position to the (2,) flood centroid."""
    p = np.asarray(leader_positions_en_m, dtype=float)
    c = np.asarray(flood_centroid_en_m, dtype=float)[:2]
    return np.linalg.norm(p[..., :2] - c, axis=-1)
