"""Scenario resolution at the ground station: a scenario file made into one frozen :class:`Scenario`.

The schema (home, fleet and pads, camera, radio, kinematics, control) is the leaf package ``mission_plan``; this
module adds what needs the world: ``launch_en_m = "auto"`` puts the launch site just outside the flood's initial
edge (see :func:`auto_launch`), which needs the flood model of ``mock_autopilot.world``. The ground station resolves
a scenario once and hands each child process its slice as a plan file (``gcs.plan``), so nothing on a drone imports
this module. The names of the schema stay importable from here. Any error raises :class:`ScenarioError` whose
one-line message names the field (an unknown key also names the closest known key).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from mission_plan.fleet import VehicleSpec, build_fleet
from mission_plan.home import GeodeticHome
from mission_plan.scenario_files import apply_override, scenario_path
from mission_plan.scenario_files import load_scenario as load_plan_scenario
from mission_plan.scenario_schema import CameraSpec, RadioSpec, Scenario
from mission_plan.scenario_schema import scenario_from_table as plan_scenario_from_table
from mission_plan.scenarios import SCENARIO_DIR, scenario_names
from mission_plan.table_fields import ScenarioError, number
from mock_autopilot.world.config import flood_model_from_config

__all__ = [
    "SCENARIO_DIR", "CameraSpec", "GeodeticHome", "RadioSpec", "Scenario", "ScenarioError", "VehicleSpec",
    "apply_override", "auto_launch", "build_fleet", "check_flood", "load_scenario", "scenario_from_table",
    "scenario_names", "scenario_path",
]


def auto_launch(fleet: Mapping[str, Any], flood_table: Mapping[str, Any], seed: int,
                source_dir: Path) -> dict[str, Any]:
    """``launch_en_m = "auto"``: the launch site just outside the flood's edge at t = 0, along ``launch_bearing_deg``.

    Takes the initial boundary point furthest along the bearing (counter-clockwise from east) from the flood's
    centroid and steps ``launch_clearance_m`` (default 2 m, as in `circle`: pads at 14 m for a 12 m flood)
    further out. Returns the fleet table with ``launch_en_m`` and ``flood_center_en_m`` filled in.
    """
    try:
        flood = flood_model_from_config(flood_table, seed=seed, base_dir=source_dir)
    except ValueError as exc:
        raise ScenarioError(str(exc)) from None
    bearing = math.radians(number(fleet, "launch_bearing_deg", 0.0, "fleet"))
    clearance = number(fleet, "launch_clearance_m", 2.0, "fleet", non_negative=True)
    centre = flood.centroid_en_m(0.0)
    ring = flood.boundary_en_m(0.0)
    direction = (math.cos(bearing), math.sin(bearing))
    rel = ring - centre
    vertex = ring[int((rel[:, 0] * direction[0] + rel[:, 1] * direction[1]).argmax())]
    out = vertex - centre
    out_norm = max(math.hypot(out[0], out[1]), 1e-9)
    launch = vertex + clearance * out / out_norm
    table = dict(fleet)
    table["launch_en_m"] = [float(launch[0]), float(launch[1])]
    table["flood_center_en_m"] = [float(centre[0]), float(centre[1])]
    return table


def scenario_from_table(raw: Mapping[str, Any], default_name: str = "scenario",
                        source_dir: Path = SCENARIO_DIR) -> Scenario:
    """Validate a parsed scenario table, resolving "auto" launch pads with the flood model."""
    return plan_scenario_from_table(raw, default_name, source_dir, resolve_launch=auto_launch)


def load_scenario(name_or_path: str, overrides: Sequence[str] = ()) -> Scenario:
    """Read a scenario by bundled name or path and apply ``key=value`` overrides, resolving "auto" launch pads."""
    return load_plan_scenario(name_or_path, overrides, resolve_launch=auto_launch)


def check_flood(scenario: Scenario) -> None:
    """Build the flood model once so a bad ``[flood]`` table (an unknown key too) fails before anything starts."""
    try:
        flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
    except ValueError as exc:
        raise ScenarioError(str(exc)) from None
