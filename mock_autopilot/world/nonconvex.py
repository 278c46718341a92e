"""The non-convex flood of SPEC §3: ``r(θ,t) = R(t)(1 + a3 cos 3θ + a5 cos(5θ + φ))`` with R growing linearly."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mock_autopilot.world.growth import growth_fraction
from mission_plan.geometry import ring_area_centroid


_TABLE_SIZE = 1 << 16
"""Angles in ``NonConvexFlood``'s shape table: the radius read from it is within ``R·(3a3 + 5a5)·2π/N`` (about
1.7 mm at R = 16 m) of the formula; points nearer the edge than that are checked exactly."""


@dataclass(frozen=True)
class NonConvexFlood:
    """A star-shaped flood with three and five lobes; ``phase_rad`` is φ (drawn from the seed by the config)."""

    center_en_m: tuple[float, float] = (0.0, 0.0)
    radius_start_m: float = 12.0
    radius_end_m: float = 16.0
    growth_duration_s: float = 60.0
    amplitude_3: float = 0.2
    amplitude_5: float = 0.1
    phase_rad: float = 0.0
    boundary_vertices: int = 512

    def base_radius_m(self, t_s: float) -> float:
        """R(t) [m]."""
        return self.radius_start_m + (self.radius_end_m - self.radius_start_m) * growth_fraction(
            t_s, self.growth_duration_s
        )

    def shape_factor(self, cos_t: NDArray[np.float64], sin_t: NDArray[np.float64]) -> NDArray[np.float64]:
        """``1 + a3 cos 3θ + a5 cos(5θ + φ)`` from cos θ and sin θ (Chebyshev forms, no arctan needed)."""
        c2 = cos_t * cos_t
        s2 = sin_t * sin_t
        cos3 = cos_t * (4.0 * c2 - 3.0)
        cos5 = cos_t * (16.0 * c2 * c2 - 20.0 * c2 + 5.0)
        sin5 = sin_t * (16.0 * s2 * s2 - 20.0 * s2 + 5.0)
        cos5p = cos5 * math.cos(self.phase_rad) - sin5 * math.sin(self.phase_rad)
        return 1.0 + self.amplitude_3 * cos3 + self.amplitude_5 * cos5p

    @cached_property
    def _shape_table(self) -> NDArray[np.float64]:
        """``shape_factor`` at ``_TABLE_SIZE`` angles round the circle (bin ``k`` covers [k, k+1)·2π/N)."""
        theta = (np.arange(_TABLE_SIZE) + 0.5) * (2.0 * math.pi / _TABLE_SIZE)
        return self.shape_factor(np.cos(theta), np.sin(theta))

    def is_water(self, points_en_m: ArrayLike, t_s: float) -> NDArray[np.bool_]:
        """Exact, but fast for a camera's 20 000 points: the shape factor is read from a fine table of angles, and
        only the few points closer to the edge than the table's error are decided with the exact formula."""
        p = np.asarray(points_en_m, dtype=float)
        de = p[..., 0] - self.center_en_m[0]
        dn = p[..., 1] - self.center_en_m[1]
        r2 = de * de + dn * dn
        radius = self.base_radius_m(t_s)
        # float32 atan2 (vectorised, ~1e-6 rad) only picks the table bin; the doubled margin below covers it.
        angle = np.arctan2(dn.astype(np.float32), de.astype(np.float32))
        index = (angle * np.float32(_TABLE_SIZE / (2.0 * math.pi)) + np.float32(_TABLE_SIZE)).astype(np.int32)
        edge_r = radius * self._shape_table[index & (_TABLE_SIZE - 1)]
        water = r2 <= edge_r * edge_r
        slope = 3.0 * abs(self.amplitude_3) + 5.0 * abs(self.amplitude_5)
        margin_m = 2.0 * radius * slope * (2.0 * math.pi / _TABLE_SIZE) + 1e-9
        unsure = np.abs(r2 - edge_r * edge_r) <= 2.0 * edge_r * margin_m + margin_m * margin_m
        if unsure.any():
            du, nu = de[unsure], dn[unsure]
            ru = np.maximum(np.hypot(du, nu), 1e-12)
            water[unsure] = ru <= radius * self.shape_factor(du / ru, nu / ru)
        return water

    def boundary_en_m(self, t_s: float) -> NDArray[np.float64]:
        theta = np.linspace(0.0, 2.0 * math.pi, self.boundary_vertices, endpoint=False)
        c, s = np.cos(theta), np.sin(theta)
        r = self.base_radius_m(t_s) * self.shape_factor(c, s)
        return np.stack([self.center_en_m[0] + r * c, self.center_en_m[1] + r * s], axis=-1)

    def area_m2(self, t_s: float) -> float:
        """``π R² (1 + (a3² + a5²)/2)``: the integral of r²/2 over θ."""
        radius = self.base_radius_m(t_s)
        return math.pi * radius * radius * (1.0 + 0.5 * (self.amplitude_3**2 + self.amplitude_5**2))

    def centroid_en_m(self, t_s: float) -> NDArray[np.float64]:
        """Off the centre in general (the lobes' cubic cross terms), so computed from a fine boundary ring."""
        return ring_area_centroid(self.boundary_en_m(t_s))[1]
