"""The downward camera's geometry (SPEC §3): a nadir pinhole camera over flat ground.

A nadir pinhole camera at height h with horizontal field of view ``fov`` sees a ground rectangle whose width is
``2 h tan(fov/2)``; with square pixels every pixel covers the same ground distance, so the image is an
orthographic map of the footprint. Image up is the vehicle's forward direction, image right its right.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from mission_plan.geometry import footprint_side_m


@dataclass(frozen=True)
class CameraModel:
    """A downward camera: image size [px] and horizontal field of view [deg] (across the image width)."""

    width_px: int = 128
    height_px: int = 128
    fov_deg: float = 60.0

    def __post_init__(self) -> None:
        if not (isinstance(self.width_px, int) and isinstance(self.height_px, int)):
            raise ValueError("camera.width_px/height_px: must be integers")
        if not (8 <= self.width_px <= 4096 and 8 <= self.height_px <= 4096):
            raise ValueError("camera.width_px/height_px: must be between 8 and 4096 pixels")
        if not (math.isfinite(self.fov_deg) and 0.0 < self.fov_deg < 170.0):
            raise ValueError("camera.fov_deg: must be in (0, 170) degrees")

    def footprint_side_m(self, altitude_m: float) -> float:
        """Ground width of the image [m]: ``2 h tan(fov/2)`` (SPEC §3); a plain number is computed without numpy
        (every rendered frame asks twice), with the same arithmetic as ``mission_plan.geometry.footprint_side_m``."""
        if isinstance(altitude_m, float):
            return 2.0 * altitude_m * math.tan(math.radians(self.fov_deg) / 2.0) if altitude_m > 0.0 else 0.0
        return float(footprint_side_m(altitude_m, self.fov_deg))

    def footprint_height_m(self, altitude_m: float) -> float:
        """Ground extent along the image's vertical axis [m] (equal to the side for a square image)."""
        return self.footprint_side_m(altitude_m) * self.height_px / self.width_px

    def ground_sample_m(self, altitude_m: float) -> float:
        """Ground distance covered by one pixel [m/px]."""
        return self.footprint_side_m(altitude_m) / self.width_px
