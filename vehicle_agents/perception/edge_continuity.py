"""Which of a frame's edge points a boundary drone reports: those continuous with the edge it tracks.

The ground station cages the flood with the edge points each boundary drone's camera saw (paper §III-B;
:mod:`gcs.polygon.caged`). A frame can hold a second, false boundary besides the shore: the edge of a cloud shadow
across turbid water, a band of glint. Its pixels are boundary pixels like the shore's, metres inside the water, and
where one drone is the only camera on that stretch of the edge the ground station's outlier test (a median over
the neighbourhood) has nothing to outvote them with, so the rescue centre's polygon gets a notch.

The shore the drone tracks runs through the middle of its image (eq 5 keeps it there), so its points are found by
starting at the edge point nearest the tracked edge below the drone and walking out along the tangent in both
directions, keeping each point that continues the last kept one: no further across the normal than a pixel-scale
step plus a bend of at most ``MAX_SLOPE`` (a 45° turn at 1) over the gap between them, the bend capped at
``MAX_BEND_M`` however long the gap. A second boundary metres away does not continue the first, whatever its
length; the shore's own curvature (a 12 m radius bends by ~0.3 m over 3 m) always does.

Pure: numpy arrays in, a subset of the same points out, in their order along the tangent.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

STEP_TOLERANCE_M = 0.5
"""How far across the normal the next point may step beyond the bend allowance [m] (pixel noise is ~0.1 m)."""
MAX_SLOPE = 1.0
"""The steepest bend followed between two neighbouring points [m across per m along]."""
MAX_BEND_M = 1.0
"""The bend allowance grows with the gap along the edge up to this much [m]: past a gap, a boundary further across
than the step and this is another one."""
MIN_POINTS = 3
"""Fewer points than this are reported as they are: there is no edge to be continuous with."""


def continuous_edge_points(points_en_m: NDArray[np.float64], tangent_en: NDArray[np.float64],
                           normal_en: NDArray[np.float64], footprint_side_m: float) -> NDArray[np.float64]:
    """The points (K, 2) [m; E, N, relative to the drone] continuous with the edge through the middle of the image.

    The walk starts at the point nearest, along the tangent and across the normal, to the median edge position
    across the middle sixth of the footprint (the edge the improved law tracks,
    :func:`vehicle_agents.control.vision_tracking.tracked_offset_en_m`). A frame whose neighbouring points all
    continue each other (one boundary, the usual case) is returned whole without the walk.
    """
    points = np.asarray(points_en_m, dtype=float).reshape(-1, 2)
    if points.shape[0] < MIN_POINTS:
        return points
    along_m = points @ np.asarray(tangent_en, dtype=float)
    order = np.argsort(along_m, kind="stable")
    points, along_m = points[order], along_m[order]
    across_m = points @ np.asarray(normal_en, dtype=float)
    steps_ok = np.abs(np.diff(across_m)) <= STEP_TOLERANCE_M + np.minimum(MAX_SLOPE * np.diff(along_m), MAX_BEND_M)
    if steps_ok.all():
        return points
    band = max(footprint_side_m / 6.0, 0.5)
    middle = across_m[np.abs(along_m) <= band]
    anchor = float(np.median(middle if middle.size else across_m))
    start = int(np.argmin(along_m * along_m + (across_m - anchor) ** 2))
    along, across = along_m.tolist(), across_m.tolist()
    keep = [False] * len(along)
    keep[start] = True
    for step in (1, -1):
        last_along, last_across = along[start], across[start]
        for j in range(start + step, len(along) if step > 0 else -1, step):
            bend_m = min(MAX_SLOPE * abs(along[j] - last_along), MAX_BEND_M)
            if abs(across[j] - last_across) <= STEP_TOLERANCE_M + bend_m:
                keep[j] = True
                last_along, last_across = along[j], across[j]
    return points[np.array(keep)]
