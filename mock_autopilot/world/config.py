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
  fractal (``terrain_size_m``, ``cell_m``, ``basin_scale_m``, ``relief_m``, ``roughness``, ``terrain_seed``;
  heights are metres above the source) or a DEM image ``dem_path`` (16-bit or 8-bit single-channel PNG/TIFF read
  with OpenCV; ``dem_cell_m``, ``dem_height_scale_m`` per count, ``dem_height_offset_m``, ``dem_center_en_m``;
  image row 0 is the north edge).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from mock_autopilot.world.flood_model import ExpandingCircle, FloodModel


class FloodConfigError(ValueError):
    """An invalid ``[flood]`` table; the message names the offending field (``flood.<key>: ...``)."""


class _Fields:
    """Reads typed fields out of a table and remembers which keys were used, to reject unknown keys."""

    def __init__(self, table: Mapping[str, Any], base_dir: Path, prefix: str = "flood") -> None:
        self.table = table
        self.base_dir = base_dir
        self.prefix = prefix
        self.used: set[str] = {"model"}

    def name(self, key: str) -> str:
        return f"{self.prefix}.{key}"

    def number(self, key: str, default: float, *, positive: bool = False, non_negative: bool = False) -> float:
        self.used.add(key)
        value = self.table.get(key, default)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise FloodConfigError(f"{self.name(key)}: must be a number, got {value!r}")
        value = float(value)
        if not math.isfinite(value):
            raise FloodConfigError(f"{self.name(key)}: must be finite, got {value!r}")
        if positive and value <= 0.0:
            raise FloodConfigError(f"{self.name(key)}: must be > 0, got {value:g}")
        if non_negative and value < 0.0:
            raise FloodConfigError(f"{self.name(key)}: must be >= 0, got {value:g}")
        return value

    def integer(self, key: str, default: int) -> int:
        self.used.add(key)
        value = self.table.get(key, default)
        if isinstance(value, bool) or not isinstance(value, int):
            raise FloodConfigError(f"{self.name(key)}: must be an integer, got {value!r}")
        return value

    def pair(self, key: str, default: tuple[float, float], *, positive: bool = False) -> tuple[float, float]:
        self.used.add(key)
        value = self.table.get(key, default)
        if not isinstance(value, (list, tuple)) or len(value) != 2:
            raise FloodConfigError(f"{self.name(key)}: must be a pair [a, b] of numbers, got {value!r}")
        out = []
        for item in value:
            if isinstance(item, bool) or not isinstance(item, (int, float)) or not math.isfinite(float(item)):
                raise FloodConfigError(f"{self.name(key)}: must be a pair of finite numbers, got {value!r}")
            if positive and float(item) <= 0.0:
                raise FloodConfigError(f"{self.name(key)}: both values must be > 0, got {value!r}")
            out.append(float(item))
        return (out[0], out[1])

    def text(self, key: str, default: str | None) -> str | None:
        self.used.add(key)
        value = self.table.get(key, default)
        if value is not None and not isinstance(value, str):
            raise FloodConfigError(f"{self.name(key)}: must be a string, got {value!r}")
        return value

    def reject_unknown(self) -> None:
        unknown = sorted(set(self.table) - self.used)
        if unknown:
            raise FloodConfigError(f"{self.name(unknown[0])}: unknown key for model {self.table.get('model')!r}")

    def growth(self, start_key: str, end_key: str, start: float, end: float) -> None:
        if end < start:
            raise FloodConfigError(
                f"{self.name(end_key)}: must be >= {self.name(start_key)} ({start:g}); floods grow, got {end:g}"
            )


def _circle(f: _Fields, seed: int) -> FloodModel:
    center = f.pair("center_en_m", (0.0, 0.0))
    r0 = f.number("radius_start_m", 12.0, positive=True)
    r1 = f.number("radius_end_m", 16.0, positive=True)
    f.growth("radius_start_m", "radius_end_m", r0, r1)
    duration = f.number("growth_duration_s", 60.0, positive=True)
    return ExpandingCircle(center_en_m=center, radius_start_m=r0, radius_end_m=r1, growth_duration_s=duration)


_BUILDERS: dict[str, Callable[[_Fields, int], FloodModel]] = {"circle": _circle}

MODEL_NAMES: tuple[str, ...] = ("circle", "ellipse", "nonconvex", "drift", "terrain")


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
    fields = _Fields(table, Path(base_dir) if base_dir is not None else Path.cwd())
    flood = _BUILDERS[model](fields, int(seed))
    fields.reject_unknown()
    return flood
