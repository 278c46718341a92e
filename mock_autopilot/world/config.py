"""Build a flood model from a scenario's ``[flood]`` table, with one clear error per bad field (SPEC §3, §4).

Keys per model (every length in metres, every time in seconds on the flood clock; values hold before t = 0 and
after the growth ends):

- ``circle`` (the paper's flood): ``center_en_m = [e, n]``, ``radius_start_m``, ``radius_end_m``,
  ``growth_duration_s``.
- ``ellipse``: ``center_en_m``, ``semi_axes_start_m = [a, b]``, ``semi_axes_end_m = [a, b]`` (each axis grows
  at its own rate), ``orientation_deg`` (direction of the ``a`` axis, counter-clockwise from east),
  ``growth_duration_s``.
- ``nonconvex``: ``center_en_m``, ``radius_start_m``, ``radius_end_m``, ``growth_duration_s``, ``amplitude_3``
  (0.2), ``amplitude_5`` (0.1), ``phase_rad`` (default: drawn from the seed) for
  ``r(θ,t) = R(t)(1 + a3 cos 3θ + a5 cos(5θ + φ))``.
- ``drift``: a shape (``shape = "circle" | "ellipse" | "nonconvex"`` with that shape's keys) whose centre moves at
  ``velocity_en_mps = [ve, vn]`` for ``drift_duration_s`` (default: ``growth_duration_s``).
- ``terrain``: water rising from ``level_start_m`` to ``level_end_m`` over ``growth_duration_s`` on a heightmap;
  the flood is the connected part of {height < level} that holds ``source_en_m``. Heightmap: either a seeded
  fractal basin (``terrain_size_m``, ``cell_m``, ``basin_scale_m``, ``relief_m``, ``roughness`` in [0, 1],
  ``terrain_seed``, default the scenario seed; heights ``relief_m·(r/basin_scale_m)² + relief_m/8·noise`` in metres
  above the source, see ``heightmap.fractal_basin``) or a DEM image ``dem_path`` (16-bit or 8-bit single-channel
  PNG/TIFF read with OpenCV; ``dem_cell_m``, ``dem_height_scale_m`` per count, ``dem_height_offset_m``,
  ``dem_center_en_m``; image row 0 is the north edge).
- ``hydro``: a shallow-water run (ANUGA) over a seeded landform or a DEM, with sources, rain and boundaries; see
  ``hydro_config`` for its keys.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from mock_autopilot.world.drift import DriftingFlood
from mock_autopilot.world.ellipse import GrowingEllipse
from mock_autopilot.world.flood_fields import FloodConfigError, Fields, dem_heightmap
from mock_autopilot.world.flood_model import ExpandingCircle, FloodModel
from mock_autopilot.world.heightmap import fractal_basin
from mock_autopilot.world.hydro_config import hydro_flood
from mock_autopilot.world.nonconvex import NonConvexFlood
from mock_autopilot.world.terrain import TerrainFlood


def _circle(f: Fields, seed: int) -> FloodModel:
    center = f.pair("center_en_m", (0.0, 0.0))
    r0 = f.number("radius_start_m", 12.0, positive=True)
    r1 = f.number("radius_end_m", 16.0, positive=True)
    f.growth("radius_start_m", "radius_end_m", r0, r1)
    duration = f.number("growth_duration_s", 60.0, non_negative=True)
    return ExpandingCircle(center_en_m=center, radius_start_m=r0, radius_end_m=r1, growth_duration_s=duration)


def _ellipse(f: Fields, seed: int) -> FloodModel:
    center = f.pair("center_en_m", (0.0, 0.0))
    axes0 = f.pair("semi_axes_start_m", (14.0, 9.0), positive=True)
    axes1 = f.pair("semi_axes_end_m", (19.0, 12.0), positive=True)
    if axes1[0] < axes0[0] or axes1[1] < axes0[1]:
        raise FloodConfigError(
            f"{f.name('semi_axes_end_m')}: each semi-axis must be >= {f.name('semi_axes_start_m')} "
            f"{list(axes0)}; floods grow, got {list(axes1)}"
        )
    return GrowingEllipse(
        center_en_m=center,
        semi_axes_start_m=axes0,
        semi_axes_end_m=axes1,
        orientation_deg=f.number("orientation_deg", 0.0),
        growth_duration_s=f.number("growth_duration_s", 60.0, non_negative=True),
    )


def _nonconvex(f: Fields, seed: int) -> FloodModel:
    center = f.pair("center_en_m", (0.0, 0.0))
    r0 = f.number("radius_start_m", 12.0, positive=True)
    r1 = f.number("radius_end_m", 16.0, positive=True)
    f.growth("radius_start_m", "radius_end_m", r0, r1)
    a3 = f.number("amplitude_3", 0.2)
    a5 = f.number("amplitude_5", 0.1)
    if abs(a3) + abs(a5) >= 1.0:
        raise FloodConfigError(
            f"{f.name('amplitude_5')}: |amplitude_3| + |amplitude_5| must be < 1 so the radius stays positive, "
            f"got {abs(a3) + abs(a5):g}"
        )
    drawn_phase = float(np.random.default_rng([int(seed) & 0xFFFFFFFF, 0x9A5E]).uniform(0.0, 2.0 * math.pi))
    return NonConvexFlood(
        center_en_m=center,
        radius_start_m=r0,
        radius_end_m=r1,
        growth_duration_s=f.number("growth_duration_s", 60.0, non_negative=True),
        amplitude_3=a3,
        amplitude_5=a5,
        phase_rad=f.number("phase_rad", drawn_phase),
    )


_SHAPES: dict[str, Callable[[Fields, int], FloodModel]] = {
    "circle": _circle,
    "ellipse": _ellipse,
    "nonconvex": _nonconvex,
}


def _drift(f: Fields, seed: int) -> FloodModel:
    shape_name = f.text("shape", "circle")
    if shape_name not in _SHAPES:
        raise FloodConfigError(f"{f.name('shape')}: unknown shape {shape_name!r}; expected one of {', '.join(_SHAPES)}")
    shape = _SHAPES[shape_name](f, seed)
    growth_s = f.number("growth_duration_s", 60.0, non_negative=True)
    return DriftingFlood(
        shape=shape,
        velocity_en_mps=f.pair("velocity_en_mps", (0.12, 0.09)),
        drift_duration_s=f.number("drift_duration_s", growth_s, non_negative=True),
    )


def _terrain(f: Fields, seed: int) -> FloodModel:
    source = f.pair("source_en_m", (0.0, 0.0))
    level0 = f.number("level_start_m", 1.0)
    level1 = f.number("level_end_m", 2.0)
    f.growth("level_start_m", "level_end_m", level0, level1)
    duration = f.number("growth_duration_s", 60.0, non_negative=True)
    heightmap = dem_heightmap(f, source)
    if heightmap is None:
        size = f.number("terrain_size_m", 120.0, positive=True)
        cell = f.number("cell_m", 0.5, positive=True)
        cells = size / cell
        if not 8 <= cells <= MAX_TERRAIN_CELLS:
            raise FloodConfigError(
                f"{f.name('cell_m')}: terrain_size_m / cell_m = {cells:g} cells a side; "
                f"must be 8 .. {MAX_TERRAIN_CELLS}"
            )
        roughness = f.number("roughness", 0.5, non_negative=True)
        if roughness > 1.0:
            raise FloodConfigError(f"{f.name('roughness')}: must be in [0, 1], got {roughness:g}")
        heightmap = fractal_basin(
            size_m=size,
            cell_m=cell,
            basin_scale_m=f.number("basin_scale_m", 30.0, positive=True),
            relief_m=f.number("relief_m", 4.0, positive=True),
            roughness=roughness,
            seed=f.integer("terrain_seed", seed),
            source_en_m=source,
        )
    if not heightmap.contains(np.asarray(source)):
        raise FloodConfigError(f"{f.name('source_en_m')}: {list(source)} lies outside the terrain")
    flood = TerrainFlood(heightmap, source, level0, level1, duration)
    ground_m = float(heightmap.heights_m[flood.source_cell()])
    if ground_m >= level0:
        raise FloodConfigError(
            f"{f.name('level_start_m')}: {level0:g} m is not above the ground at the source ({ground_m:.3g} m); "
            "the flood would be empty"
        )
    cells_end = flood.flooded_cells(level1)
    if cells_end[0, :].any() or cells_end[-1, :].any() or cells_end[:, 0].any() or cells_end[:, -1].any():
        raise FloodConfigError(
            f"{f.name('level_end_m')}: at {level1:g} m the water reaches the edge of the terrain; "
            "lower it or use a larger terrain"
        )
    return flood


_BUILDERS: dict[str, Callable[[Fields, int], FloodModel]] = {
    **_SHAPES,
    "drift": _drift,
    "terrain": _terrain,
    "hydro": hydro_flood,
}

MAX_TERRAIN_CELLS = 2048
"""Largest fractal terrain side [cells] (the refined grid for area and boundary is 4x this)."""

MODEL_NAMES: tuple[str, ...] = ("circle", "ellipse", "nonconvex", "drift", "terrain", "hydro")


def flood_model_from_config(
    table: Mapping[str, Any], seed: int = 0, base_dir: str | Path | None = None
) -> FloodModel:
    """The flood model a scenario's ``[flood]`` table describes (see the module docstring for the keys).

    ``seed`` draws whatever the table leaves random (the non-convex phase, the fractal terrain);
    ``base_dir`` resolves a relative ``dem_path`` (the scenario file's folder; default: the working directory).
    Raises ``FloodConfigError`` naming the field.
    """
    if not isinstance(table, Mapping):
        raise FloodConfigError(f"flood: must be a table, got {type(table).__name__}")
    model = table.get("model", "circle")
    if not isinstance(model, str) or model not in _BUILDERS:
        raise FloodConfigError(f"flood.model: unknown model {model!r}; expected one of {', '.join(MODEL_NAMES)}")
    fields = Fields(table, Path(base_dir) if base_dir is not None else Path.cwd())
    flood = _BUILDERS[model](fields, int(seed))
    fields.reject_unknown()
    return flood
