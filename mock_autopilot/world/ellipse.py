"""An ellipse whose two semi-axes grow at different rates: the simplest anisotropic flood (SPEC §3)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mock_autopilot.world.growth import growth_fraction


@dataclass(frozen=True)
class GrowingEllipse:
    """Semi-axes (a, b) grow linearly from ``semi_axes_start_m`` to ``semi_axes_end_m`` over ``growth_duration_s``;
    the ``a`` axis points ``orientation_deg`` counter-clockwise from east."""

    center_en_m: tuple[float, float] = (0.0, 0.0)
    semi_axes_start_m: tuple[float, float] = (14.0, 9.0)
    semi_axes_end_m: tuple[float, float] = (19.0, 12.0)
    orientation_deg: float = 0.0
    growth_duration_s: float = 60.0
    boundary_vertices: int = 256

    def semi_axes_m(self, t_s: float) -> tuple[float, float]:
        """(a, b) [m] at flood time ``t_s``."""
        f = growth_fraction(t_s, self.growth_duration_s)
        a0, b0 = self.semi_axes_start_m
        a1, b1 = self.semi_axes_end_m
        return a0 + (a1 - a0) * f, b0 + (b1 - b0) * f

    def is_water(self, points_en_m: ArrayLike, t_s: float) -> NDArray[np.bool_]:
        p = np.asarray(points_en_m, dtype=float)
        a, b = self.semi_axes_m(t_s)
        c, s = math.cos(math.radians(self.orientation_deg)), math.sin(math.radians(self.orientation_deg))
        de = p[..., 0] - self.center_en_m[0]
        dn = p[..., 1] - self.center_en_m[1]
        u = (c * de + s * dn) / a
        v = (-s * de + c * dn) / b
        return u * u + v * v <= 1.0

    def boundary_en_m(self, t_s: float) -> NDArray[np.float64]:
        a, b = self.semi_axes_m(t_s)
        theta = np.linspace(0.0, 2.0 * math.pi, self.boundary_vertices, endpoint=False)
        u, v = a * np.cos(theta), b * np.sin(theta)
        c, s = math.cos(math.radians(self.orientation_deg)), math.sin(math.radians(self.orientation_deg))
        return np.stack([self.center_en_m[0] + c * u - s * v, self.center_en_m[1] + s * u + c * v], axis=-1)

    def area_m2(self, t_s: float) -> float:
        a, b = self.semi_axes_m(t_s)
        return math.pi * a * b

    def centroid_en_m(self, t_s: float) -> NDArray[np.float64]:
        return np.array(self.center_en_m, dtype=float)
