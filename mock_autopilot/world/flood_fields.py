"""Typed reads of a ``[flood]`` table (or one of its sub-tables) that name the field in every error."""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from mission_plan.unknown_keys import first_unknown, unknown_key_message
from mock_autopilot.world.heightmap import Heightmap, HeightmapError, load_dem


class FloodConfigError(ValueError):
    """An invalid ``[flood]`` table; the message names the offending field (``flood.<key>: ...``)."""


class Fields:
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

    def numbers(self, key: str, default: tuple[float, ...], *, non_negative: bool = False) -> tuple[float, ...]:
        """A non-empty list of finite numbers."""
        self.used.add(key)
        value = self.table.get(key, default)
        if not isinstance(value, (list, tuple)) or not value or any(
                isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)) for v in value):
            raise FloodConfigError(f"{self.name(key)}: must be a non-empty list of finite numbers, got {value!r}")
        if non_negative and min(float(v) for v in value) < 0.0:
            raise FloodConfigError(f"{self.name(key)}: every value must be >= 0, got {min(value):g}")
        return tuple(float(v) for v in value)

    def text(self, key: str, default: str | None) -> str | None:
        self.used.add(key)
        value = self.table.get(key, default)
        if value is not None and not isinstance(value, str):
            raise FloodConfigError(f"{self.name(key)}: must be a string, got {value!r}")
        return value

    def reject_unknown(self) -> None:
        """A key the model never read is a typo or belongs to another model: name it and the closest key it reads."""
        unknown = first_unknown(self.table, self.used)
        if unknown is not None:
            raise FloodConfigError(unknown_key_message(
                self.prefix, unknown, self.used, what=f"unknown key for model {self.table.get('model')!r}"))

    def growth(self, start_key: str, end_key: str, start: float, end: float) -> None:
        if end < start:
            raise FloodConfigError(
                f"{self.name(end_key)}: must be >= {self.name(start_key)} ({start:g}); floods grow, got {end:g}"
            )


def dem_heightmap(f: Fields, default_center_en_m: tuple[float, float]) -> Heightmap | None:
    """The DEM named by ``dem_path`` (with ``dem_cell_m``, ``dem_height_scale_m`` per count, ``dem_height_offset_m``,
    ``dem_center_en_m``; a relative path is taken from the scenario's folder), or None without ``dem_path``."""
    dem_path = f.text("dem_path", None)
    if dem_path is None:
        return None
    path = Path(dem_path) if Path(dem_path).is_absolute() else f.base_dir / dem_path
    cell = f.number("dem_cell_m", 1.0, positive=True)
    scale = f.number("dem_height_scale_m", 0.01, positive=True)
    offset = f.number("dem_height_offset_m", 0.0)
    center = f.pair("dem_center_en_m", default_center_en_m)
    try:
        return load_dem(path, cell, scale, offset, center)
    except HeightmapError as exc:
        raise FloodConfigError(f"{f.name('dem_path')}: {exc}") from None
