"""Area coverage and overlap efficiency (SPEC §5), sampled on a grid.

Coverage is the fraction of the flood inside the union of the camera footprints. A footprint is the square of side
``2 h tan(fov/2)`` under a downward camera. The MissionRecord carries no yaw, so footprints are AXIS-ALIGNED
(sides along east and north) by default; pass ``yaw_enu_rad`` for yaw-aligned squares.

Unioning hundreds of shapely squares per time step is slow, so the flood is rasterised on a fixed grid of cell
centres (``CoverageGrid``) and footprints are rasterised onto the same grid: axis-aligned squares with a 2-D
difference array (fully vectorised), yaw-aligned ones cell by cell inside their bounding box. Each footprint's
water area comes from a summed-area table. Areas are counted in cells, so coverage, its upper bound
``min(1, Σ footprint water area / flood area)`` and the overlap efficiency ``union ÷ Σ footprint water area``
are consistent with each other (coverage ≤ upper bound always holds).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mission_plan.geometry import footprint_side_m

__all__ = ["CoverageGrid", "CoverageStats", "footprint_coverage", "footprint_side_m"]


@dataclass(frozen=True)
class CoverageGrid:
    """A regular grid of cell centres: x = x0 + (i + ½)·cell, y = y0 + (j + ½)·cell [m; east, north]."""

    x0_m: float
    y0_m: float
    cell_m: float
    nx: int
    ny: int

    @staticmethod
    def around(min_en_m: ArrayLike, max_en_m: ArrayLike, max_cells_per_side: int = 240, min_cell_m: float = 0.05) -> "CoverageGrid":
        """A grid over the box [min, max] (plus one cell of margin) with at most ``max_cells_per_side`` cells."""
        lo = np.asarray(min_en_m, dtype=float)
        hi = np.asarray(max_en_m, dtype=float)
        extent = float(max(np.max(hi - lo), 1e-6))
        cell = max(extent / max(max_cells_per_side - 2, 1), min_cell_m)
        nx = int(math.ceil((hi[0] - lo[0]) / cell)) + 2
        ny = int(math.ceil((hi[1] - lo[1]) / cell)) + 2
        return CoverageGrid(float(lo[0] - cell), float(lo[1] - cell), cell, nx, ny)

    @property
    def cell_area_m2(self) -> float:
        return self.cell_m * self.cell_m

    def centres_en_m(self) -> NDArray[np.float64]:
        """(ny, nx, 2) cell centres."""
        x = self.x0_m + (np.arange(self.nx) + 0.5) * self.cell_m
        y = self.y0_m + (np.arange(self.ny) + 0.5) * self.cell_m
        xx, yy = np.meshgrid(x, y)
        return np.stack([xx, yy], axis=-1)


@dataclass(frozen=True)
class CoverageStats:
    """Coverage of the flood by a set of footprints at one time (areas in m², on the grid)."""

    coverage: float
    upper_bound: float
    overlap_efficiency: float
    flood_area_m2: float
    union_water_m2: float
    sum_water_m2: float


def _index_ranges(grid: CoverageGrid, centres: NDArray[np.float64], half: NDArray[np.float64]) -> tuple[NDArray[np.int_], ...]:
    """Inclusive cell index ranges [i_lo, i_hi] x [j_lo, j_hi] whose centres lie in each axis-aligned box."""
    i_lo = np.ceil((centres[:, 0] - half - grid.x0_m) / grid.cell_m - 0.5).astype(int)
    i_hi = np.floor((centres[:, 0] + half - grid.x0_m) / grid.cell_m - 0.5).astype(int)
    j_lo = np.ceil((centres[:, 1] - half - grid.y0_m) / grid.cell_m - 0.5).astype(int)
    j_hi = np.floor((centres[:, 1] + half - grid.y0_m) / grid.cell_m - 0.5).astype(int)
    return (
        np.clip(i_lo, 0, grid.nx),
        np.clip(i_hi, -1, grid.nx - 1),
        np.clip(j_lo, 0, grid.ny),
        np.clip(j_hi, -1, grid.ny - 1),
    )


def footprint_coverage(
    grid: CoverageGrid,
    water_mask: NDArray[np.bool_],
    centres_en_m: ArrayLike,
    sides_m: ArrayLike,
    yaw_enu_rad: ArrayLike | None = None,
) -> CoverageStats:
    """Coverage statistics of the (ny, nx) water mask by square footprints centred at (n, 2) points.

    Footprints with a side <= 0 or a non-finite centre are ignored (vehicles on the ground or lost).
    """
    water = np.asarray(water_mask, dtype=bool)
    centres = np.asarray(centres_en_m, dtype=float).reshape(-1, 2)
    sides = np.asarray(sides_m, dtype=float).ravel()
    use = np.all(np.isfinite(centres), axis=1) & np.isfinite(sides) & (sides > 0.0)
    centres, sides = centres[use], sides[use]
    yaws = None if yaw_enu_rad is None else np.asarray(yaw_enu_rad, dtype=float).ravel()[use]

    flood_cells = int(water.sum())
    flood_area = flood_cells * grid.cell_area_m2
    if flood_cells == 0:
        return CoverageStats(math.nan, math.nan, math.nan, 0.0, 0.0, 0.0)
    if len(centres) == 0:
        return CoverageStats(0.0, 0.0, math.nan, flood_area, 0.0, 0.0)

    if yaws is None:
        covered, per_footprint_water = _axis_aligned(grid, water, centres, sides)
    else:
        covered, per_footprint_water = _yaw_aligned(grid, water, centres, sides, yaws)
    union_cells = int(np.count_nonzero(covered & water))
    sum_cells = int(per_footprint_water.sum())
    return CoverageStats(
        coverage=union_cells / flood_cells,
        upper_bound=min(1.0, sum_cells / flood_cells),
        overlap_efficiency=union_cells / sum_cells if sum_cells > 0 else math.nan,
        flood_area_m2=flood_area,
        union_water_m2=union_cells * grid.cell_area_m2,
        sum_water_m2=sum_cells * grid.cell_area_m2,
    )


def _axis_aligned(
    grid: CoverageGrid, water: NDArray[np.bool_], centres: NDArray[np.float64], sides: NDArray[np.float64]
) -> tuple[NDArray[np.bool_], NDArray[np.int_]]:
    i_lo, i_hi, j_lo, j_hi = _index_ranges(grid, centres, sides / 2.0)
    nonempty = (i_hi >= i_lo) & (j_hi >= j_lo)
    i_lo, i_hi, j_lo, j_hi = i_lo[nonempty], i_hi[nonempty], j_lo[nonempty], j_hi[nonempty]
    diff = np.zeros((grid.ny + 1, grid.nx + 1), dtype=np.int32)
    np.add.at(diff, (j_lo, i_lo), 1)
    np.add.at(diff, (j_lo, i_hi + 1), -1)
    np.add.at(diff, (j_hi + 1, i_lo), -1)
    np.add.at(diff, (j_hi + 1, i_hi + 1), 1)
    covered = np.cumsum(np.cumsum(diff, axis=0), axis=1)[: grid.ny, : grid.nx] > 0
    table = np.zeros((grid.ny + 1, grid.nx + 1), dtype=np.int64)
    table[1:, 1:] = np.cumsum(np.cumsum(water, axis=0), axis=1)
    per = table[j_hi + 1, i_hi + 1] - table[j_lo, i_hi + 1] - table[j_hi + 1, i_lo] + table[j_lo, i_lo]
    return covered, per


def _yaw_aligned(
    grid: CoverageGrid,
    water: NDArray[np.bool_],
    centres: NDArray[np.float64],
    sides: NDArray[np.float64],
    yaws: NDArray[np.float64],
) -> tuple[NDArray[np.bool_], NDArray[np.int_]]:
    covered = np.zeros_like(water)
    per = np.zeros(len(centres), dtype=np.int64)
    half_diag = sides / math.sqrt(2.0)
    i_lo, i_hi, j_lo, j_hi = _index_ranges(grid, centres, half_diag)
    for k in range(len(centres)):
        if i_hi[k] < i_lo[k] or j_hi[k] < j_lo[k]:
            continue
        xs = grid.x0_m + (np.arange(i_lo[k], i_hi[k] + 1) + 0.5) * grid.cell_m - centres[k, 0]
        ys = grid.y0_m + (np.arange(j_lo[k], j_hi[k] + 1) + 0.5) * grid.cell_m - centres[k, 1]
        c, s = math.cos(yaws[k]), math.sin(yaws[k])
        along = c * xs[None, :] + s * ys[:, None]
        across = -s * xs[None, :] + c * ys[:, None]
        inside = (np.abs(along) <= sides[k] / 2.0) & (np.abs(across) <= sides[k] / 2.0)
        window = (slice(j_lo[k], j_hi[k] + 1), slice(i_lo[k], i_hi[k] + 1))
        covered[window] |= inside
        per[k] = int(np.count_nonzero(inside & water[window]))
    return covered, per
