"""The tilt a multicopter shows for a horizontal acceleration, for simulators that do not integrate attitude.

A multicopter accelerates horizontally by tilting its thrust: at acceleration ``a`` (and holding height) its body
leans ``atan(a / g)`` towards it, nose down to speed up forwards, right side down to speed up to the right. The
camera is fixed to the body, so this is how far its view leaves the nadir.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

GRAVITY_MPS2 = 9.80665


def tilt_from_acceleration_rad(accel_ned_mps2: ArrayLike, yaw_ned_rad: ArrayLike) -> NDArray[np.float64]:
    """(N, 2) body (roll, pitch) [rad] for (N, 3) NED accelerations [m/s²] and (N,) PX4 yaws [rad]."""
    a = np.asarray(accel_ned_mps2, dtype=float).reshape(-1, 3)
    yaw = np.asarray(yaw_ned_rad, dtype=float).reshape(-1)
    c, s = np.cos(yaw), np.sin(yaw)
    forward = c * a[:, 0] + s * a[:, 1]
    right = -s * a[:, 0] + c * a[:, 1]
    return np.stack([np.arctan2(right, GRAVITY_MPS2), -np.arctan2(forward, GRAVITY_MPS2)], axis=-1)

