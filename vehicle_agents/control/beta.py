"""The separating term of eqs 6-7 (boundary drones) and eq 10 (followers).

Eq 7 is the 7th-order smooth step ``β(x) = 1 − 35(x/d)⁴ + 84(x/d)⁵ − 70(x/d)⁶ + 20(x/d)⁷`` for x < d, 0 beyond:
it falls smoothly from 1 at x = 0 to 0 at x = d with zero slope at both ends. The paper's sentence "β is negative"
is wrong as printed (β ∈ [0, 1]); the repulsion comes from the direction of ``v`` in eq 6, which the paper calls a
"constant vector". Reading (SPEC §2): ``v`` = gain × the unit vector from neighbour h to this drone, so each
neighbour closer than d pushes the drone straight away from it, by up to ``gain`` m/s.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def beta(distance_m: ArrayLike, d_m: float) -> NDArray[np.float64]:
    """Eq 7, vectorised: 1 at 0, 0.5 at d/2, 0 at and beyond d."""
    r = np.asarray(distance_m, dtype=float) / d_m
    inside = (r >= 0.0) & (r < 1.0)
    rc = np.clip(r, 0.0, 1.0)
    value = 1.0 - 35.0 * rc**4 + 84.0 * rc**5 - 70.0 * rc**6 + 20.0 * rc**7
    return np.where(inside, value, 0.0)


def separation_velocity(
    own_en_m: NDArray[np.float64], others_en_m: NDArray[np.float64], d_m: float, gain_mps: float
) -> NDArray[np.float64]:
    """Eq 6 (and eq 10's last term): ``Σ_h β(‖q − q_h‖) · gain · (q − q_h)/‖q − q_h‖`` [m/s; E, N].

    Neighbours at exactly the same point give no direction and are skipped.
    """
    others = np.asarray(others_en_m, dtype=float).reshape(-1, 2)
    if others.shape[0] == 0 or gain_mps == 0.0:
        return np.zeros(2)
    diff = np.asarray(own_en_m, dtype=float)[None, :] - others
    dist = np.hypot(diff[:, 0], diff[:, 1])
    ok = dist > 1e-9
    if not np.any(ok):
        return np.zeros(2)
    weights = beta(dist[ok], d_m) * gain_mps / dist[ok]
    return (weights[:, None] * diff[ok]).sum(axis=0)
