"""The non-convex flood of SPEC §3: ``r(θ,t) = R(t)(1 + a3 cos 3θ + a5 cos(5θ + φ))`` with R growing linearly."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mock_autopilot.world.growth import growth_fraction
from mock_autopilot.world.ring_geometry import ring_area_centroid


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

    def is_water(self, points_en_m: ArrayLike, t_s: float) -> NDArray[np.bool_]:
        p = np.asarray(points_en_m, dtype=float)
        de = p[..., 0] - self.center_en_m[0]
        dn = p[..., 1] - self.center_en_m[1]
        r = np.hypot(de, dn)
        safe = np.maximum(r, 1e-12)
        return r <= self.base_radius_m(t_s) * self.shape_factor(de / safe, dn / safe)

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
