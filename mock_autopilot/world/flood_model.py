"""The one interface every flood model answers (SPEC §3), and the paper's expanding circle.

All coordinates are mission ENU metres (east, north); time is seconds on the flood clock, which starts when every
vehicle is airborne in OFFBOARD (SPEC §4).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray


@runtime_checkable
class FloodModel(Protocol):
    """A flood whose extent is known at every time: the ground truth for the camera and the metrics."""

    def is_water(self, points_en_m: ArrayLike, t_s: float) -> NDArray[np.bool_]:
        """Whether each point of an (..., 2) array of (east, north) metres is under water at time ``t_s``."""
        ...

    def boundary_en_m(self, t_s: float) -> NDArray[np.float64]:
        """The outer boundary as a (K, 2) counter-clockwise ring of (east, north) metres, not closed."""
        ...

    def area_m2(self, t_s: float) -> float:
        """The flooded area [m²] (islands excluded where the model has them)."""
        ...

    def centroid_en_m(self, t_s: float) -> NDArray[np.float64]:
        """The centroid of the flooded region [m; ENU east, north]."""
        ...


@runtime_checkable
class DepthField(Protocol):
    """A flood that knows how deep its water is (the hydro model); water is where the depth exceeds ``wet_depth_m``."""

    wet_depth_m: float

    def depth_m(self, points_en_m: ArrayLike, t_s: float) -> NDArray[np.float32]:
        """Water depth [m] at each (..., 2) point at time ``t_s``."""
        ...

    def depth_on_affine_grid_m(self, points_en_m: NDArray[np.float64], t_s: float,
                               shape_hw: tuple[int, int] | None = None) -> NDArray[np.float32]:
        """``depth_m`` for an (H, W, 2) grid of points affine in its indices (faster; the camera's footprint); with
        ``shape_hw`` only the grid's first 2x2 points are given."""
        ...

    def flow_at_mps(self, point_en_m: ArrayLike, t_s: float) -> tuple[float, float]:
        """Surface flow velocity [m/s; east, north] at one point (the camera draws it as streaks)."""
        ...


@dataclass(frozen=True)
class ExpandingCircle:
    """The paper's flood (§IV): a circle whose radius grows linearly, 12 m -> 16 m over 60 s in ``circle``.

    Before t = 0 the radius is ``radius_start_m``; after ``growth_duration_s`` it stays at ``radius_end_m``.
    """

    center_en_m: tuple[float, float] = (0.0, 0.0)
    radius_start_m: float = 12.0
    radius_end_m: float = 16.0
    growth_duration_s: float = 60.0
    boundary_vertices: int = 256

    def radius_m(self, t_s: float) -> float:
        """Radius [m] at flood time ``t_s``."""
        frac = min(max(t_s / self.growth_duration_s, 0.0), 1.0) if self.growth_duration_s > 0 else 1.0
        return self.radius_start_m + (self.radius_end_m - self.radius_start_m) * frac

    def is_water(self, points_en_m: ArrayLike, t_s: float) -> NDArray[np.bool_]:
        p = np.asarray(points_en_m, dtype=float)
        d2 = (p[..., 0] - self.center_en_m[0]) ** 2 + (p[..., 1] - self.center_en_m[1]) ** 2
        return d2 <= self.radius_m(t_s) ** 2

    def boundary_en_m(self, t_s: float) -> NDArray[np.float64]:
        theta = np.linspace(0.0, 2.0 * math.pi, self.boundary_vertices, endpoint=False)
        r = self.radius_m(t_s)
        return np.stack([self.center_en_m[0] + r * np.cos(theta), self.center_en_m[1] + r * np.sin(theta)], axis=-1)

    def area_m2(self, t_s: float) -> float:
        return math.pi * self.radius_m(t_s) ** 2

    def centroid_en_m(self, t_s: float) -> NDArray[np.float64]:
        return np.array(self.center_en_m, dtype=float)
