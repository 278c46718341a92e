"""Scenario files: a bundled name or a TOML path, read into a table, ``key=value`` overrides applied, validated.

Reading a scenario here needs nothing but this package, so a drone's companion computer can do it as a local
convenience (``python -m vehicle_agents --scenario circle``). A scenario whose pads are ``"auto"`` needs the
flood model: the ground station passes its resolver (``gcs.scenario.load_scenario``) and writes plan files.
"""

from __future__ import annotations

import tomllib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from mission_plan.scenario_schema import LaunchResolver, Scenario, scenario_from_table
from mission_plan.scenarios import SCENARIO_DIR, scenario_names
from mission_plan.table_fields import ScenarioError


def parse_value(text: str) -> Any:
    """An override's value as TOML would read it (numbers, booleans, arrays, quoted strings); bare words are strings."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def apply_override(table: dict[str, Any], assignment: str) -> None:
    """Apply one ``dotted.key=value`` to a nested table in place (unknown keys are caught by validation)."""
    key, sep, value = assignment.partition("=")
    key = key.strip()
    if not sep or not key or any(not part for part in key.split(".")):
        raise ScenarioError(f"--set {assignment!r}: expected key=value, e.g. flood.radius_end_m=20")
    parts = key.split(".")
    node = table
    for depth, part in enumerate(parts[:-1]):
        child = node.setdefault(part, {})
        if not isinstance(child, dict):
            raise ScenarioError(f"{'.'.join(parts[:depth + 1])}: is not a table, cannot set {key}")
        node = child
    node[parts[-1]] = parse_value(value.strip())


def scenario_path(name_or_path: str) -> Path:
    """A bundled scenario's file, or the given path."""
    candidate = Path(name_or_path)
    if candidate.suffix == ".toml" or candidate.exists():
        if not candidate.is_file():
            raise ScenarioError(f"scenario: no such file {name_or_path}")
        return candidate
    bundled = SCENARIO_DIR / f"{name_or_path}.toml"
    if not bundled.is_file():
        raise ScenarioError(f"scenario: unknown scenario {name_or_path!r} (known: {', '.join(scenario_names())})")
    return bundled


def read_scenario_table(path: Path, overrides: Sequence[str] = ()) -> dict[str, Any]:
    """The scenario file's table with the overrides applied (not validated yet)."""
    try:
        raw: dict[str, Any] = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"scenario: {path.name} is not valid TOML ({exc})") from None
    except OSError as exc:
        raise ScenarioError(f"scenario: cannot read {path} ({exc.strerror or exc})") from None
    for assignment in overrides:
        apply_override(raw, assignment)
    return raw


def load_scenario(name_or_path: str, overrides: Sequence[str] = (),
                  resolve_launch: LaunchResolver | None = None) -> Scenario:
    """Read a scenario by bundled name or path and apply ``key=value`` overrides (dotted keys into the tables).

    Without ``resolve_launch`` a scenario with ``launch_en_m = "auto"`` raises :class:`ScenarioError`.
    """
    path = scenario_path(name_or_path)
    raw = read_scenario_table(path, overrides)
    return scenario_from_table(raw, default_name=path.stem, source_dir=path.resolve().parent,
                               resolve_launch=resolve_launch)
