"""What the onboard vision tells the control law, as one small frozen value.

Offsets are metres on the ground relative to the point straight below the drone, along world axes
(east, north): the perception step is given the drone's yaw and rotates image axes into the world.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class PerceptionResult:
    """One frame's measurement. ``has_edge`` is Algorithm 1's test: both land and water are in view."""

    has_edge: bool
    water_fraction: float
    only_land: bool
    only_water: bool
    footprint_side_m: float
    midpoint_offset_en_m: NDArray[np.float64] | None = None
    """p − q of eq 5: midpoint of the land and water centroids, relative to the drone [m; east, north]."""
    water_centroid_en_m: NDArray[np.float64] | None = None
    land_centroid_en_m: NDArray[np.float64] | None = None
    edge_normal_en: NDArray[np.float64] | None = None
    """Unit vector across the edge, pointing from water to land."""
    edge_tangent_en: NDArray[np.float64] | None = None
    """Unit vector along the edge with water on its left (counter-clockwise round the flood)."""
    edge_points_en_m: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)))
    """Boundary pixels seen, as (K, 2) offsets from the drone [m; east, north]."""
    shore_points_en_m: NDArray[np.float64] | None = None
    """Where the grey-water cue split the frame: the shore placed again by colour along the boundary steps of the
    edge points (:mod:`vehicle_agents.perception.shore`), one per edge point and in their order, (K, 2) offsets
    like them, what the drone reports of the shore; None where the edge points are the shore already (the blue
    cue) or colour cannot place it."""
    water_centroid_px: NDArray[np.float64] | None = None
    """Water centroid in the image [px; column, row from the top-left corner, pixel centres at +0.5]."""
    land_centroid_px: NDArray[np.float64] | None = None
    """Land centroid in the image [px; column, row]."""
    ground_sample_m: float = float("nan")
    """Ground distance of one pixel [m/px] at the altitude given (at the image centre when tilted)."""
    water_mask: NDArray[np.bool_] | None = None
    """(H, W) pixels classified as water, when the frame held both classes (for overlays and scoring)."""

    @staticmethod
    def no_measurement(footprint_side_m: float = 0.0) -> "PerceptionResult":
        """A well-defined empty result for unusable input (empty image, NaN altitude, zero field of view)."""
        return PerceptionResult(
            has_edge=False, water_fraction=float("nan"), only_land=False, only_water=False, footprint_side_m=footprint_side_m
        )
