"""Ground heights on a regular grid: a seeded fractal basin or a user's DEM image (SPEC §3, terrain flood).

Grid convention: row 0 is the north edge, column 0 the west edge, cell ``(row, col)`` has its centre at
``east = cx + (col + ½ − cols/2)·cell``, ``north = cy − (row + ½ − rows/2)·cell`` around
``center_en_m = (cx, cy)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from mock_autopilot.world.fractal import fractal_noise

OUTSIDE_HEIGHT_M = 1.0e6
"""Height reported off the grid: high ground, never flooded."""


class HeightmapError(ValueError):
    """A DEM that cannot be used (unreadable, not single-channel, too small)."""


@dataclass(frozen=True, eq=False)
class Heightmap:
    """Heights [m] on a north-up grid of square cells."""

    heights_m: NDArray[np.float32]
    cell_m: float
    center_en_m: tuple[float, float] = (0.0, 0.0)

    @property
    def shape(self) -> tuple[int, int]:
        rows, cols = self.heights_m.shape
        return rows, cols

    def grid_coordinates(self, points_en_m: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Fractional (col, row) of each (..., 2) point, cell centres at integers (OpenCV's remap convention)."""
        p = np.asarray(points_en_m, dtype=float)
        rows, cols = self.shape
        col = (p[..., 0] - self.center_en_m[0]) / self.cell_m + cols / 2.0 - 0.5
        row = -(p[..., 1] - self.center_en_m[1]) / self.cell_m + rows / 2.0 - 0.5
        return col, row

    def point_coordinates(self, east_m: float, north_m: float) -> tuple[float, float]:
        """:meth:`grid_coordinates` of one point in the same arithmetic on plain floats (no array round trip: the
        camera asks for one point per frame)."""
        rows, cols = self.shape
        cx, cy = self.center_en_m
        return ((east_m - cx) / self.cell_m + cols / 2.0 - 0.5, -(north_m - cy) / self.cell_m + rows / 2.0 - 0.5)

    def cell_centres_en_m(self, rows_idx: ArrayLike, cols_idx: ArrayLike) -> NDArray[np.float64]:
        """(…, 2) east/north [m] of cell centres at (possibly fractional) grid indices."""
        rows, cols = self.shape
        r = np.asarray(rows_idx, dtype=float)
        c = np.asarray(cols_idx, dtype=float)
        east = self.center_en_m[0] + (c + 0.5 - cols / 2.0) * self.cell_m
        north = self.center_en_m[1] - (r + 0.5 - rows / 2.0) * self.cell_m
        return np.stack([east, north], axis=-1)

    def height_at(self, points_en_m: ArrayLike) -> NDArray[np.float64]:
        """Bilinearly interpolated height [m] at each (..., 2) point; ``OUTSIDE_HEIGHT_M`` off the grid."""
        col, row = self.grid_coordinates(points_en_m)
        return sample_grid(self.heights_m, col, row, cv2.INTER_LINEAR, OUTSIDE_HEIGHT_M).astype(float)

    def contains(self, point_en_m: ArrayLike) -> bool:
        """Whether a point lies on the grid."""
        col, row = self.grid_coordinates(point_en_m)
        rows, cols = self.shape
        return bool(-0.5 <= float(col) <= cols - 0.5 and -0.5 <= float(row) <= rows - 0.5)


def sample_grid(
    grid: NDArray[np.generic], col: NDArray[np.float64], row: NDArray[np.float64], interpolation: int, outside: float
) -> NDArray[np.generic]:
    """Sample a 2-D grid at fractional (col, row) of any shape with OpenCV's remap (points laid out in blocks)."""
    shape = np.shape(col)
    n = int(np.prod(shape)) if shape else 1
    if n == 0:
        return np.zeros(shape, dtype=grid.dtype)
    width = min(n, 4096)
    rows_needed = -(-n // width)
    map_x = np.full(rows_needed * width, -10.0, np.float32)
    map_y = np.full(rows_needed * width, -10.0, np.float32)
    map_x[:n] = np.ravel(col)
    map_y[:n] = np.ravel(row)
    out = cv2.remap(
        grid,
        map_x.reshape(rows_needed, width),
        map_y.reshape(rows_needed, width),
        interpolation,
        borderMode=cv2.BORDER_CONSTANT,
        borderValue=outside,
    )
    return out.reshape(-1)[:n].reshape(shape)


def fractal_basin(
    size_m: float,
    cell_m: float,
    basin_scale_m: float,
    relief_m: float,
    roughness: float,
    seed: int,
    source_en_m: tuple[float, float] = (0.0, 0.0),
) -> Heightmap:
    """A seeded basin around ``source_en_m``: a bowl plus fractal relief, heights in metres above the source.

    ``height = relief_m · (r / basin_scale_m)² + relief_m/8 · noise`` where ``r`` is the distance from the source and
    ``noise`` is unit fractal noise with spectrum ``1/f^(2 − roughness)`` (roughness 0: smooth hills, 1: rough and
    broken shores, with more islands and bays). Shifted so the source is at height 0.
    """
    n = max(int(round(size_m / cell_m)), 8)
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, 0x7E22A1])
    noise = fractal_noise(n, 2.0 - roughness, rng)
    grid = Heightmap(np.zeros((n, n), np.float32), cell_m, source_en_m)
    rows_idx, cols_idx = np.mgrid[0:n, 0:n]
    centres = grid.cell_centres_en_m(rows_idx, cols_idx)
    r = np.hypot(centres[..., 0] - source_en_m[0], centres[..., 1] - source_en_m[1])
    heights = relief_m * (r / basin_scale_m) ** 2 + (relief_m / 8.0) * noise
    basin = Heightmap(heights.astype(np.float32), cell_m, source_en_m)
    offset = float(basin.height_at(np.asarray(source_en_m, dtype=float)))
    return Heightmap((heights - offset).astype(np.float32), cell_m, source_en_m)


def load_dem(
    path: Path, cell_m: float, height_scale_m: float, height_offset_m: float, center_en_m: tuple[float, float]
) -> Heightmap:
    """A DEM image (16-bit or 8-bit single-channel PNG/TIFF, row 0 north) as heights ``count · scale + offset``."""
    if not path.is_file():
        raise HeightmapError(f"no such file: {path}")
    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise HeightmapError(f"cannot read {path} as an image")
    if image.ndim != 2:
        raise HeightmapError(f"{path} has {image.shape[2]} channels; a DEM must be single-channel (grey)")
    if image.dtype not in (np.uint8, np.uint16, np.int16, np.float32):
        raise HeightmapError(f"{path} has pixel type {image.dtype}; expected 8/16-bit or float32")
    if min(image.shape) < 8:
        raise HeightmapError(f"{path} is {image.shape[1]}x{image.shape[0]} px; at least 8x8 needed")
    heights = image.astype(np.float64) * height_scale_m + height_offset_m
    if not np.all(np.isfinite(heights)) or math.isnan(float(heights.mean())):
        raise HeightmapError(f"{path} holds non-finite heights")
    return Heightmap(heights.astype(np.float32), cell_m, center_en_m)
