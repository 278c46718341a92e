"""Write a resolved scenario's plan files: one agent plan per vehicle, the fleet plan and the cameras plan.

The ground station resolves the scenario once (defaults, ``--set``, seed, "auto" pads with the flood model);
every child then reads its own file instead of resolving the scenario again, so no child needs the ground
station's code and all agree on one plan by construction. The mission key (:mod:`comms.key_file`) travels with
the plans: ``mission.key`` in the same folder, mode 0600, new for every mission unless one is given.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

from comms.key_file import KEY_FILE_NAME, create_key_file, read_key_file, write_key_file
from comms.signing import MissionKey
from mission_plan.plan_files import write_plan
from mission_plan.plans import agent_plan, cameras_plan, fleet_plan
from mission_plan.scenario_schema import Scenario

FLEET_PLAN_NAME = "fleet.json"
CAMERAS_PLAN_NAME = "cameras.json"


@dataclass(frozen=True)
class PlanPaths:
    """Where a run's plan files are: the folder, the fleet's and the cameras' plans, and each vehicle's."""

    folder: Path
    fleet: Path
    cameras: Path
    agents: Mapping[int, Path]
    key: Path


def agent_plan_name(vehicle_id: int) -> str:
    """``agent_<id>.json``."""
    return f"agent_{vehicle_id}.json"


def plan_paths(folder: Path, vehicle_ids: Iterable[int]) -> PlanPaths:
    """The file names of a run's plans under ``folder`` (pure)."""
    return PlanPaths(folder=folder, fleet=folder / FLEET_PLAN_NAME, cameras=folder / CAMERAS_PLAN_NAME,
                     agents={vid: folder / agent_plan_name(vid) for vid in vehicle_ids}, key=folder / KEY_FILE_NAME)


def write_plans(scenario: Scenario, mode: str, folder: Path, mission: str | None = None,
                key_file: Path | None = None) -> PlanPaths:
    """Write every plan of ``scenario`` flown in ``mode`` under ``folder``, and the mission key: a new one, or the
    one in ``key_file`` copied in (mode 0600); returns their paths.

    Raises ``ScenarioError`` (bad mode or control table) or ``KeyFileError`` (``key_file`` unusable) before any
    file is written.
    """
    paths = plan_paths(folder, (v.vehicle_id for v in scenario.vehicles))
    given: MissionKey | None = None if key_file is None else read_key_file(key_file)
    agents = {vid: agent_plan(scenario, vid, mode, mission) for vid in paths.agents}
    write_plan(paths.fleet, fleet_plan(scenario, mission))
    write_plan(paths.cameras, cameras_plan(scenario, mission))
    for vid, plan in agents.items():
        write_plan(paths.agents[vid], plan)
    if given is None:
        create_key_file(paths.key)
    else:
        write_key_file(paths.key, given)
    return paths
