"""Typed fields read out of a scenario's TOML tables, every failure one line naming the field.

The scenario schema (:mod:`mission_plan.scenario_schema`, :mod:`mission_plan.fleet`) and the ground
station's resolution (``gcs.scenario``) read their tables through these, so a bad value always reads
``where.key: must be ..., got ...`` and an unknown key ``where.key: unknown key (did you mean where.other?)``.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping
from typing import Any

from mission_plan.unknown_keys import dotted, first_unknown, unknown_key_message


class ScenarioError(ValueError):
    """A scenario file or override is invalid; the one-line message names the field."""


def number(table: Mapping[str, Any], key: str, default: float, where: str, *, positive: bool = False,
           non_negative: bool = False, minimum: float | None = None, maximum: float | None = None) -> float:
    """A finite number (an integer is read as a float), with optional bounds."""
    value = table.get(key, default)
    name = dotted(where, key)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(float(value)):
        raise ScenarioError(f"{name}: must be a finite number, got {value!r}")
    value = float(value)
    if positive and value <= 0.0:
        raise ScenarioError(f"{name}: must be > 0, got {value:g}")
    if non_negative and value < 0.0:
        raise ScenarioError(f"{name}: must be >= 0, got {value:g}")
    if minimum is not None and value < minimum:
        raise ScenarioError(f"{name}: must be >= {minimum:g}, got {value:g}")
    if maximum is not None and value > maximum:
        raise ScenarioError(f"{name}: must be <= {maximum:g}, got {value:g}")
    return value


def integer(table: Mapping[str, Any], key: str, default: int, where: str, minimum: int = 0) -> int:
    """An integer (not a boolean) of at least ``minimum``."""
    value = table.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise ScenarioError(f"{dotted(where, key)}: must be an integer >= {minimum}, got {value!r}")
    return value


def pair(table: Mapping[str, Any], key: str, default: tuple[float, float], where: str) -> tuple[float, float]:
    """Two finite numbers ``[east, north]``."""
    value = table.get(key, list(default))
    if not isinstance(value, (list, tuple)) or len(value) != 2 or not all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(float(v)) for v in value
    ):
        raise ScenarioError(f"{dotted(where, key)}: must be a pair [east, north] of numbers, got {value!r}")
    return float(value[0]), float(value[1])


def sub_table(raw: Mapping[str, Any], key: str) -> dict[str, Any]:
    """A nested table (empty when absent)."""
    value = raw.get(key, {})
    if not isinstance(value, dict):
        raise ScenarioError(f"{key}: must be a table, got {value!r}")
    return value


def reject_unknown(table: Mapping[str, Any], known: Collection[str], where: str) -> None:
    """Raise on the first key of ``table`` not in ``known``, naming the closest known key."""
    unknown = first_unknown(table, known)
    if unknown is not None:
        raise ScenarioError(unknown_key_message(where, unknown, known))
