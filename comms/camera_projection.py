"""Where a body-fixed downward camera's pixels land on flat ground: one homography, used by the simulated camera
and by onboard perception alike (the law is the pinhole camera's, not a choice of either side).

The camera looks along the body's down axis (no gimbal), image up = body forward, image right = body right, with
square pixels and horizontal field of view ``fov`` across the image width. A pixel at continuous image coordinates
(x right, y down; pixel centres at +0.5) is the body ray ``(k (H/2 − y), k (x − W/2), 1)`` (forward, right, down)
with ``k = tan(fov/2) / (W/2)``; rotated into NED by the attitude (:func:`comms.frames.body_to_ned_matrix`) it meets
the ground ``h`` below at ``h (d_e, d_n) / d_d``. Level, this is SPEC §3's nadir map (``2 h tan(fov/2) / W`` metres
per pixel); tilted by θ the footprint's centre moves ``h tan θ`` the way the camera now points.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from comms.frames import body_to_ned_matrix

MIN_RAY_DOWN = 0.17
"""A frame whose corner rays point less steeply down than this (the cosine of 80° from vertical) sees the horizon,
not the ground below: no ground projection is made for it."""


def pixel_to_ground(width_px: int, height_px: int, fov_deg: float, height_m: float, roll_rad: float,
                    pitch_rad: float, yaw_ned_rad: float) -> NDArray[np.float64] | None:
    """3x3 homography from image (x, y, 1) to homogeneous ground offsets (east, north, 1) [m] from the point below
    the camera, or None when part of the image sees above the ground's horizon."""
    k = math.tan(math.radians(fov_deg) / 2.0) / (width_px / 2.0)
    to_body = np.array([[0.0, -k, k * height_px / 2.0], [k, 0.0, -k * width_px / 2.0], [0.0, 0.0, 1.0]])
    to_ned = body_to_ned_matrix(roll_rad, pitch_rad, yaw_ned_rad) @ to_body
    (a, b, c), (d, e, f), (g, h, i) = to_ned.tolist()
    for x, y in ((0.0, 0.0), (width_px, 0.0), (0.0, height_px), (width_px, height_px)):
        north, east, down = a * x + b * y + c, d * x + e * y + f, g * x + h * y + i
        if down < MIN_RAY_DOWN * math.sqrt(north * north + east * east + down * down):
            return None
    pick_en = np.array([[0.0, height_m, 0.0], [height_m, 0.0, 0.0], [0.0, 0.0, 1.0]])
    return pick_en @ to_ned


def project_pixels(homography: NDArray[np.float64], x: NDArray[np.float64], y: NDArray[np.float64]
                   ) -> NDArray[np.float64]:
    """(..., 2) ground offsets [m; east, north] of image points (x, y) [px] through ``homography``.

    A level camera's homography has no perspective row (``g20 = g21 = 0``): its denominator is the constant ``g22``
    at every finite point, so it is divided by directly, the same arithmetic with two array operations fewer per
    coordinate (a perception frame projects its edge points through here)."""
    (g00, g01, g02), (g10, g11, g12), (g20, g21, g22) = homography.tolist()
    w = g22 if g20 == 0.0 and g21 == 0.0 else g20 * x + g21 * y + g22
    east = g00 * x + g01 * y + g02
    ground = np.empty(np.shape(east) + (2,))
    np.divide(east, w, out=ground[..., 0])
    np.divide(g10 * x + g11 * y + g12, w, out=ground[..., 1])
    return ground
