"""A flood that flows: depth rasters of a shallow-water run, replayed on the flood clock (SPEC §3).

Flood time t maps to hydraulic time ``start_s + time_scale · t`` (held at the ends of the run); the depth there is
the linear blend of the two recorded frames around it, and between raster cells it is bilinear. A point is water
where that depth exceeds ``wet_depth_m``. The camera sees all the water; the outline the swarm is scored against
(``boundary_en_m``, ``area_m2``, ``centroid_en_m``) is the *caged component*: the wet component that holds the
source, or, with no source (rain), the component that overlaps most the largest component at the end of the run.
Components are traced on the depth raster resampled ``BOUNDARY_UPSAMPLE`` times finer, so they agree with
``is_water``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from mock_autopilot.world.heightmap import Heightmap, sample_grid
from mock_autopilot.world.hydro_solver import HydroRun

BOUNDARY_UPSAMPLE = 4
"""Components are traced on the depth raster resampled this many times finer."""


@dataclass(frozen=True)
class Outline:
    """The caged component at one time: outer ring, its area and centroid, and the total wet area."""

    ring_en_m: NDArray[np.float64]
    area_m2: float
    centroid_en_m: NDArray[np.float64]
    wet_area_m2: float


@dataclass(frozen=True, eq=False)
class HydroFlood:
    """The :class:`FloodModel` of a hydrodynamic run; also answers depth and ground height."""

    run: HydroRun
    anchor_en_m: tuple[float, float] | None
    """The point the caged component holds (a source); None: follow the largest component at the end."""
    wet_depth_m: float = 0.02
    time_scale: float = 1.0
    """Hydraulic seconds per flood-clock second."""
    start_s: float = 0.0
    """Hydraulic time at flood time 0 (water that has flowed before the swarm starts)."""
    manning_n: float = 0.04
    """The run's friction, for the flow speed the camera draws as streaks."""
    grid: Heightmap = field(init=False, repr=False)
    _flows: dict[int, NDArray[np.float32]] = field(init=False, repr=False, default_factory=dict)
    _outlines: dict[float, Outline] = field(init=False, repr=False, default_factory=dict)
    _target: list[NDArray[np.bool_]] = field(init=False, repr=False, default_factory=list)
    _blend: dict[float, NDArray[np.float32]] = field(init=False, repr=False, default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "grid", Heightmap(self.run.ground_m, self.run.cell_m, self.run.center_en_m))

    def hydraulic_time_s(self, t_s: float) -> float:
        """Solver time [s] at flood time ``t_s``, held within the recorded run."""
        times = self.run.times_s
        return float(min(max(self.start_s + self.time_scale * t_s, times[0]), times[-1]))

    def depth_raster_m(self, t_s: float) -> NDArray[np.float32]:
        """(rows, cols) depth [m] at flood time ``t_s``, blended between the two frames around it (read-only).

        The newest blend is kept: every camera of a fleet looks at the same flood time, so one blend serves them all.
        """
        th = self.hydraulic_time_s(t_s)
        cached = self._blend.get(th)
        if cached is not None:
            return cached
        times = self.run.times_s
        k = min(max(int(np.searchsorted(times, th, side="right")) - 1, 0), len(times) - 2)
        w = float((th - times[k]) / (times[k + 1] - times[k]))
        blend = cv2.addWeighted(self.run.depth_m[k], 1.0 - w, self.run.depth_m[k + 1], w, 0.0)
        blend.flags.writeable = False
        self._blend.clear()
        self._blend[th] = blend
        return blend

    def depth_m(self, points_en_m: ArrayLike, t_s: float) -> NDArray[np.float32]:
        """Water depth [m] at each (..., 2) point; 0 off the domain."""
        col, row = self.grid.grid_coordinates(points_en_m)
        return sample_grid(self.depth_raster_m(t_s), col, row, cv2.INTER_LINEAR, 0.0)

    def depth_on_affine_grid_m(self, points_en_m: NDArray[np.float64], t_s: float,
                               shape_hw: tuple[int, int] | None = None) -> NDArray[np.float32]:
        """``depth_m`` for an (H, W, 2) grid of points that is affine in its indices (a nadir camera's footprint):
        one ``warpAffine`` of the depth raster instead of a per-point lookup. With ``shape_hw`` = (H, W) only the
        grid's first 2x2 points need be given (they fix the affine map)."""
        h, w = shape_hw if shape_hw is not None else points_en_m.shape[:2]
        return cv2.warpAffine(self.depth_raster_m(t_s), self._to_raster(points_en_m), (w, h),
                              flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP, borderMode=cv2.BORDER_CONSTANT,
                              borderValue=0.0)

    def _to_raster(self, points_en_m: NDArray[np.float64]) -> NDArray[np.float64]:
        """2x3 affine map from (column, row) of an affine grid of points to fractional raster (column, row)."""
        h, w = points_en_m.shape[:2]
        (e0, n0), (e_col, n_col) = points_en_m[0, 0].tolist(), points_en_m[0, min(w - 1, 1)].tolist()
        e_row, n_row = points_en_m[min(h - 1, 1), 0].tolist()
        cell = self.grid.cell_m
        c0, r0 = self.grid.point_coordinates(e0, n0)
        return np.array([[(e_col - e0) / cell, (e_row - e0) / cell, c0],
                         [-(n_col - n0) / cell, -(n_row - n0) / cell, r0]])

    def flow_raster_mps(self, t_s: float) -> NDArray[np.float32]:
        """(rows, cols, 2) surface flow velocity [m/s; east, north] of the recorded frame nearest ``t_s``, estimated
        from the water surface: downhill along its slope S at Manning's speed ``h^(2/3) √S / n`` (the rasters hold
        depth only; streaks need a direction and a rough speed, not the solver's momentum)."""
        times = self.run.times_s
        k = int(np.argmin(np.abs(times - self.hydraulic_time_s(t_s))))
        cached = self._flows.get(k)
        if cached is not None:
            return cached
        depth = self.run.depth_m[k]
        d_row, d_col = np.gradient(self.run.ground_m + depth, self.grid.cell_m)
        slope_e, slope_n = d_col, -d_row
        slope = np.hypot(slope_e, slope_n)
        speed = np.where(depth > self.wet_depth_m, np.cbrt(depth) ** 2 * np.sqrt(slope) / self.manning_n, 0.0)
        scale = speed / np.maximum(slope, 1e-9)
        flow = np.dstack([-slope_e * scale, -slope_n * scale]).astype(np.float32)
        self._flows[k] = flow
        return flow

    def flow_at_mps(self, point_en_m: ArrayLike, t_s: float) -> tuple[float, float]:
        """Surface flow velocity [m/s; east, north] in the raster cell holding one point (zero off the domain)."""
        east, north = (float(v) for v in np.asarray(point_en_m, float).reshape(-1)[:2])
        col, row = self.grid.point_coordinates(east, north)
        rows, cols = self.grid.shape
        c, r = int(round(col)), int(round(row))
        if not (0 <= c < cols and 0 <= r < rows):
            return 0.0, 0.0
        flow = self.flow_raster_mps(t_s)[r, c]
        return float(flow[0]), float(flow[1])

    def ground_height_m(self, points_en_m: ArrayLike) -> NDArray[np.float64]:
        """Ground height [m] of the solver's mesh at each (..., 2) point (edge cells held beyond the domain)."""
        p = np.asarray(points_en_m, dtype=float)
        rows, cols = self.grid.shape
        if p.shape == (2,):
            return np.asarray(self._ground_at(*self._clipped_coordinates(float(p[0]), float(p[1]))))
        col, row = self.grid.grid_coordinates(p)
        col = np.clip(col, 0.0, cols - 1.0)
        row = np.clip(row, 0.0, rows - 1.0)
        return sample_grid(self.run.ground_m, col, row, cv2.INTER_LINEAR, 0.0).astype(float)

    def _clipped_coordinates(self, east_m: float, north_m: float) -> tuple[float, float]:
        """``grid_coordinates`` of one point held on the grid, in plain floats (the per-frame rangefinder reading)."""
        rows, cols = self.grid.shape
        cx, cy = self.grid.center_en_m
        col = (east_m - cx) / self.grid.cell_m + cols / 2.0 - 0.5
        row = -(north_m - cy) / self.grid.cell_m + rows / 2.0 - 0.5
        return min(max(col, 0.0), cols - 1.0), min(max(row, 0.0), rows - 1.0)

    def _ground_at(self, col: float, row: float) -> float:
        """Bilinear ground height at one fractional (col, row) on the grid (the rangefinder's single reading)."""
        g = self.run.ground_m
        c0, r0 = min(int(col), g.shape[1] - 2), min(int(row), g.shape[0] - 2)
        fc, fr = col - c0, row - r0
        top = (1.0 - fc) * float(g[r0, c0]) + fc * float(g[r0, c0 + 1])
        bottom = (1.0 - fc) * float(g[r0 + 1, c0]) + fc * float(g[r0 + 1, c0 + 1])
        return (1.0 - fr) * top + fr * bottom

    def is_water(self, points_en_m: ArrayLike, t_s: float) -> NDArray[np.bool_]:
        return self.depth_m(points_en_m, t_s) > self.wet_depth_m

    def _fine_wet(self, t_s: float) -> NDArray[np.uint8]:
        rows, cols = self.grid.shape
        k = BOUNDARY_UPSAMPLE
        fine = cv2.resize(self.depth_raster_m(t_s), (cols * k, rows * k), interpolation=cv2.INTER_LINEAR)
        return (fine > self.wet_depth_m).astype(np.uint8)

    def _fine_to_en(self, pixels: NDArray[np.float64]) -> NDArray[np.float64]:
        k = BOUNDARY_UPSAMPLE
        return self.grid.cell_centres_en_m((pixels[:, 1] + 0.5) / k - 0.5, (pixels[:, 0] + 0.5) / k - 0.5)

    def _final_target(self) -> NDArray[np.bool_]:
        """The largest wet component at the end of the run (fine grid), for floods with no source."""
        if not self._target:
            wet = self._fine_wet(float("inf"))
            n, labels, stats, _ = cv2.connectedComponentsWithStats(wet, connectivity=8)
            best = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA])) if n > 1 else -1
            self._target.append(labels == best)
        return self._target[0]

    def _caged_label(self, labels: NDArray[np.int32], n: int) -> int:
        if n <= 1:
            return -1
        if self.anchor_en_m is not None:
            col, row = self.grid.grid_coordinates(np.asarray(self.anchor_en_m, float))
            k = BOUNDARY_UPSAMPLE
            r = int(np.clip(np.rint((float(row) + 0.5) * k - 0.5), 0, labels.shape[0] - 1))
            c = int(np.clip(np.rint((float(col) + 0.5) * k - 0.5), 0, labels.shape[1] - 1))
            if labels[r, c] > 0:
                return int(labels[r, c])
            rr, cc = np.nonzero(labels > 0)
            nearest = int(np.argmin((rr - r) ** 2 + (cc - c) ** 2))
            return int(labels[rr[nearest], cc[nearest]])
        overlap = np.bincount(labels[self._final_target()], minlength=n)
        overlap[0] = 0
        if overlap.max() > 0:
            return int(np.argmax(overlap))
        return 1 + int(np.argmax(np.bincount(labels.ravel(), minlength=n)[1:]))

    def outline(self, t_s: float) -> Outline:
        """The caged component at flood time ``t_s`` (cached per hydraulic time)."""
        th = self.hydraulic_time_s(t_s)
        cached = self._outlines.get(th)
        if cached is not None:
            return cached
        wet = self._fine_wet(t_s)
        fine_cell_m = self.grid.cell_m / BOUNDARY_UPSAMPLE
        n, labels = cv2.connectedComponents(wet, connectivity=8)
        label = self._caged_label(labels, n)
        total = float(np.count_nonzero(wet)) * fine_cell_m ** 2
        anchor = np.asarray(self.anchor_en_m if self.anchor_en_m is not None else self.grid.center_en_m, float)
        if label < 0:
            result = Outline(anchor[None, :].copy(), 0.0, anchor, total)
        else:
            mask = (labels == label).astype(np.uint8)
            count = int(np.count_nonzero(mask))
            moments = cv2.moments(mask, binaryImage=True)
            centroid = self._fine_to_en(np.array([[moments["m10"] / count, moments["m01"] / count]]))[0]
            contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
            ring = self._fine_to_en(max(contours, key=cv2.contourArea).reshape(-1, 2).astype(np.float64))
            x, y = ring[:, 0], ring[:, 1]
            if float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)) < 0.0:
                ring = ring[::-1].copy()
            result = Outline(ring, count * fine_cell_m ** 2, centroid, total)
        if len(self._outlines) > 256:
            self._outlines.clear()
        self._outlines[th] = result
        return result

    def boundary_en_m(self, t_s: float) -> NDArray[np.float64]:
        return self.outline(t_s).ring_en_m

    def area_m2(self, t_s: float) -> float:
        return self.outline(t_s).area_m2

    def centroid_en_m(self, t_s: float) -> NDArray[np.float64]:
        return self.outline(t_s).centroid_en_m

    def wet_area_m2(self, t_s: float) -> float:
        """All the water's area [m²], every component (the caged one is ``area_m2``)."""
        return self.outline(t_s).wet_area_m2
