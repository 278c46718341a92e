"""A drifting flood: any shape carried along at a constant velocity while it grows (SPEC §3)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mock_autopilot.world.growth import growth_fraction
from mock_autopilot.world.flood_model import FloodModel


@dataclass(frozen=True)
class DriftingFlood:
    """``shape`` displaced by ``velocity_en_mps · t`` for t in [0, ``drift_duration_s``] (held before and after)."""

    shape: FloodModel
    velocity_en_mps: tuple[float, float] = (0.15, 0.05)
    drift_duration_s: float = 60.0

    def offset_en_m(self, t_s: float) -> NDArray[np.float64]:
        """How far the shape has drifted by flood time ``t_s`` [m; east, north]."""
        travelled_s = growth_fraction(t_s, self.drift_duration_s) * self.drift_duration_s
        return np.asarray(self.velocity_en_mps, dtype=float) * travelled_s

    def is_water(self, points_en_m: ArrayLike, t_s: float) -> NDArray[np.bool_]:
        return self.shape.is_water(np.asarray(points_en_m, dtype=float) - self.offset_en_m(t_s), t_s)

    def boundary_en_m(self, t_s: float) -> NDArray[np.float64]:
        return self.shape.boundary_en_m(t_s) + self.offset_en_m(t_s)

    def area_m2(self, t_s: float) -> float:
        return self.shape.area_m2(t_s)

    def centroid_en_m(self, t_s: float) -> NDArray[np.float64]:
        return self.shape.centroid_en_m(t_s) + self.offset_en_m(t_s)
