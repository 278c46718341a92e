"""A terrain flood: water rising over a heightmap (SPEC §3).

The flooded region at water level L is the 4-connected component of {height < L} that holds the source; dry
cells inside it are islands. Rather than labelling components at every time, we precompute once, for every cell,
its *spill level*: the lowest water level at which the source's component reaches it, i.e. over all paths from
the source the smallest value of the highest cell on the path (a priority flood: Dijkstra with max instead of +).
Then "water at time t" is just ``spill < L(t)``: exact, vectorised, and as cheap as a circle. Points between cell
centres take the bilinearly interpolated spill level, which gives smooth shorelines.
"""

from __future__ import annotations

import heapq
from dataclasses import dataclass, field

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from mission_plan.geometry import signed_area_m2
from mock_autopilot.world.growth import ramp
from mock_autopilot.world.heightmap import Heightmap, sample_grid

BOUNDARY_UPSAMPLE = 4
"""Boundary, area and centroid are traced on the spill grid resampled this many times finer."""
NEVER_M = 1.0e6
"""Spill level of cells the flood never reaches (at or above its highest level)."""


def spill_levels(
    heights_m: NDArray[np.floating],
    source_rc: tuple[int, int],
    max_level_m: float,
    min_level_m: float | None = None,
) -> NDArray[np.float32]:
    """For each cell, the lowest water level at which it joins the source's component.

    Cells that would join only at ``max_level_m`` or above are not expanded (which bounds the work to the region
    that ever floods); they get ``max(height, max_level_m)``, never below any level the flood reaches.

    With ``min_level_m`` (the lowest level the flood ever has), the component already flooded at that level is
    found in one vectorised labelling and its cells keep their own height: they are water at every level that
    matters, and any path out of that component is limited only by cells outside it (all at least
    ``min_level_m`` high), so the priority flood that starts from its rim is still exact outside it. Only the ring
    the flood grows into is then walked cell by cell.
    """
    rows, cols = heights_m.shape
    heights = np.asarray(heights_m, dtype=np.float64)
    flat = heights.ravel().tolist()
    start = source_rc[0] * cols + source_rc[1]
    if min_level_m is not None and flat[start] < min_level_m:
        below = (heights < min_level_m).astype(np.uint8)
        _, labels = cv2.connectedComponents(below, connectivity=4)
        initial = labels == labels[source_rc]
        outside = (~initial).astype(np.uint8)
        cross = cv2.getStructuringElement(cv2.MORPH_CROSS, (3, 3))
        rim = initial & (cv2.dilate(outside, cross, borderType=cv2.BORDER_CONSTANT, borderValue=0) > 0)
        spill_grid = np.full(rows * cols, NEVER_M)
        spill_grid[initial.ravel()] = heights.ravel()[initial.ravel()]
        spill = spill_grid.tolist()
        rim_idx = np.flatnonzero(rim.ravel())
        queue = list(zip(heights.ravel()[rim_idx].tolist(), rim_idx.tolist()))
        heapq.heapify(queue)
    else:
        spill = [NEVER_M] * (rows * cols)
        spill[start] = flat[start]
        queue = [(flat[start], start)]
    while queue:
        level, idx = heapq.heappop(queue)
        if level > spill[idx]:
            continue
        r, c = divmod(idx, cols)
        for n, ok in ((idx - cols, r > 0), (idx + cols, r < rows - 1), (idx - 1, c > 0), (idx + 1, c < cols - 1)):
            if ok:
                candidate = max(level, flat[n])
                if candidate < spill[n] and candidate < max_level_m:
                    spill[n] = candidate
                    heapq.heappush(queue, (candidate, n))
    levels = np.asarray(spill, dtype=np.float64).reshape(rows, cols)
    # Cells never reached keep their own height (at least max_level_m) rather than NEVER_M: interpolating between a
    # flooded cell and a dry neighbour then puts the shore where the ground meets the water, not a cell inland.
    unreached = levels >= NEVER_M
    levels[unreached] = np.maximum(heights[unreached], max_level_m)
    return levels.astype(np.float32)


@dataclass(frozen=True, eq=False)
class TerrainFlood:
    """Water rising linearly from ``level_start_m`` to ``level_end_m`` over ``growth_duration_s`` around a source."""

    heightmap: Heightmap
    source_en_m: tuple[float, float]
    level_start_m: float
    level_end_m: float
    growth_duration_s: float = 60.0
    spill_m: NDArray[np.float32] = field(init=False, repr=False)
    _traced: dict[float, tuple[NDArray[np.float64], float, NDArray[np.float64]]] = field(
        init=False, repr=False, default_factory=dict
    )

    def __post_init__(self) -> None:
        spill = spill_levels(
            self.heightmap.heights_m, self.source_cell(), self.level_end_m + 1e-6, min_level_m=self.level_start_m
        )
        object.__setattr__(self, "spill_m", spill)

    def source_cell(self) -> tuple[int, int]:
        """(row, col) of the grid cell holding the source (clamped onto the grid)."""
        col, row = self.heightmap.grid_coordinates(np.asarray(self.source_en_m, dtype=float))
        rows, cols = self.heightmap.shape
        return int(np.clip(np.rint(row), 0, rows - 1)), int(np.clip(np.rint(col), 0, cols - 1))

    def level_m(self, t_s: float) -> float:
        """Water level L(t) [m]."""
        return ramp(self.level_start_m, self.level_end_m, t_s, self.growth_duration_s)

    def flooded_cells(self, level_m: float) -> NDArray[np.bool_]:
        """Grid cells under water at a water level: the source's component of {height < level}."""
        return self.spill_m < level_m

    def is_water(self, points_en_m: ArrayLike, t_s: float) -> NDArray[np.bool_]:
        col, row = self.heightmap.grid_coordinates(points_en_m)
        return sample_grid(self.spill_m, col, row, cv2.INTER_LINEAR, NEVER_M) < self.level_m(t_s)

    def _trace(self, t_s: float) -> tuple[NDArray[np.float64], float, NDArray[np.float64]]:
        """(outer ring, area, centroid) at the level of ``t_s``, on the finely resampled spill grid (so they agree
        with ``is_water``)."""
        level = self.level_m(t_s)
        cached = self._traced.get(level)
        if cached is not None:
            return cached
        k = BOUNDARY_UPSAMPLE
        rows, cols = self.spill_m.shape
        fine = cv2.resize(self.spill_m, (cols * k, rows * k), interpolation=cv2.INTER_LINEAR)
        water = (fine < level).astype(np.uint8)
        fine_cell_m = self.heightmap.cell_m / k
        n = int(np.count_nonzero(water))
        source = np.asarray(self.source_en_m, dtype=float)
        if n == 0:
            result = (source[None, :].copy(), 0.0, source)
        else:
            moments = cv2.moments(water, binaryImage=True)
            centroid = self._fine_to_en(np.array([[moments["m10"] / n, moments["m01"] / n]]), k)[0]
            contours, _ = cv2.findContours(water, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
            outer = max(contours, key=cv2.contourArea).reshape(-1, 2).astype(np.float64)
            ring = self._fine_to_en(outer, k)
            if signed_area_m2(ring) < 0.0:
                ring = ring[::-1].copy()
            result = (ring, n * fine_cell_m * fine_cell_m, centroid)
        if len(self._traced) > 64:
            self._traced.clear()
        self._traced[level] = result
        return result

    def _fine_to_en(self, pixels: NDArray[np.float64], k: int) -> NDArray[np.float64]:
        """East/north of fine-grid pixel centres (fine pixel i spans coarse index (i + ½)/k − ½)."""
        return self.heightmap.cell_centres_en_m((pixels[:, 1] + 0.5) / k - 0.5, (pixels[:, 0] + 0.5) / k - 0.5)

    def boundary_en_m(self, t_s: float) -> NDArray[np.float64]:
        return self._trace(t_s)[0]

    def area_m2(self, t_s: float) -> float:
        return self._trace(t_s)[1]

    def centroid_en_m(self, t_s: float) -> NDArray[np.float64]:
        return self._trace(t_s)[2]
