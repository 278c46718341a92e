"""Each process's slice of a resolved scenario: the plan files a mission hands to its processes.

The ground station resolves a scenario once (defaults, ``--set``, seed, "auto" pads) and gives every child only
what it needs, as a value that travels in a file (:mod:`mission_plan.plan_files`):

- :class:`AgentPlan` for one drone's onboard computer (``python -m vehicle_agents --plan``), what a real drone's
  companion computer receives like any mission file: its own vehicle, the control parameters of the run's mode
  with the roster, the control rate, the altitude, its camera, the home and the mission seed;
- :class:`FleetPlan` for the mock PX4 fleet (``python -m mock_autopilot.sim_bridge --plan``);
- :class:`CamerasPlan` for the camera renderer (``python -m mock_autopilot.sim_bridge.cameras --plan``).

The slicing functions are pure; ``__post_init__`` checks what msgspec's types cannot (a vehicle in its own
roster, rates > 0), so a plan decoded from a file is as valid as one built here.
"""

from __future__ import annotations

from typing import Any

import msgspec

from mission_plan.control_params import ControlParams
from mission_plan.dynamics import KinematicLimits
from mission_plan.fleet import VehicleSpec
from mission_plan.home import GeodeticHome
from mission_plan.jitter import start_delays_s
from mission_plan.roles import ROLES
from mission_plan.imaging import ImagingSpec, check_imaging, mean_wind_en_mps
from mission_plan.scenario_schema import CameraSpec, Scenario
from mission_plan.table_fields import ScenarioError
from mission_plan.weather import SensorSpec, WindSpec

PLAN_TAG_FIELD = "plan"
"""The key naming a plan file's kind and version, e.g. ``"plan": "agent/1"``."""


class WorldPlan(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """What a world simulation needs to build the flood model: the ``[flood]`` table, the seed that draws whatever
    it leaves random, and the absolute folder its relative paths (a DEM image) are resolved from."""

    flood: dict[str, Any]
    seed: int
    source_dir: str


class AgentPlan(msgspec.Struct, frozen=True, forbid_unknown_fields=True, tag_field=PLAN_TAG_FIELD, tag="agent/1"):
    """One drone's mission: who it is (id, role, group, rank, layer, ref_id, GPS, pad [m; mission ENU]), the
    control parameters of the run's mode (with the roster), the control rate [Hz of mission time], the nominal
    and take-off altitude [m], its camera, the mission's home and seed, and the mission name in the Zenoh keys."""

    mission: str
    scenario: str
    vehicle: VehicleSpec
    params: ControlParams
    control_rate_hz: float
    altitude_m: float
    camera: CameraSpec
    home: GeodeticHome
    seed: int
    start_delay_s: float = 0.0
    """How long after the flood clock starts this agent starts its mission [s] (the seeded start jitter)."""

    def __post_init__(self) -> None:
        if self.vehicle.role not in ROLES:
            raise ValueError(f"vehicle.role: must be one of {', '.join(ROLES)}, got {self.vehicle.role!r}")
        entry = self.params.entry(self.vehicle.vehicle_id)
        if self.params.roster and (entry not in self.params.roster or entry.role != self.vehicle.role):
            raise ValueError(f"vehicle.vehicle_id: vehicle {self.vehicle.vehicle_id} is not in the roster as a "
                             f"{self.vehicle.role}")
        _positive("control_rate_hz", self.control_rate_hz)
        _positive("altitude_m", self.altitude_m)


class FleetPlan(msgspec.Struct, frozen=True, forbid_unknown_fields=True, tag_field=PLAN_TAG_FIELD, tag="fleet/1"):
    """The simulated fleet: every vehicle (pads, GPS, ids), home, the dynamics (PX4 limits and the response time),
    the take-off altitude [m], the control rate [Hz] (the truth is published at it), the camera, the world
    (for cameras streamed from the fleet's own process) and the weather (``[wind]``, ``[sensors]``)."""

    mission: str
    scenario: str
    vehicles: tuple[VehicleSpec, ...]
    home: GeodeticHome
    kinematics: KinematicLimits
    altitude_m: float
    seed: int
    control_rate_hz: float
    camera: CameraSpec
    world: WorldPlan
    wind: WindSpec = msgspec.field(default_factory=WindSpec)
    sensors: SensorSpec = msgspec.field(default_factory=SensorSpec)

    def __post_init__(self) -> None:
        ids = [v.vehicle_id for v in self.vehicles]
        if not ids:
            raise ValueError("vehicles: the fleet has no vehicle")
        if len(set(ids)) != len(ids) or min(ids) < 1:
            raise ValueError(f"vehicles: vehicle ids must be unique and >= 1, got {ids}")
        _positive("control_rate_hz", self.control_rate_hz)
        _positive("altitude_m", self.altitude_m)


class CamerasPlan(msgspec.Struct, frozen=True, forbid_unknown_fields=True, tag_field=PLAN_TAG_FIELD, tag="cameras/1"):
    """The camera renderer: the world, the camera and each vehicle's role (only boundary drones stream by default)."""

    mission: str
    scenario: str
    world: WorldPlan
    camera: CameraSpec
    roles: dict[int, str]
    imaging: ImagingSpec = ImagingSpec()
    wind_en_mps: tuple[float, float] = (0.0, 0.0)
    """Mean wind [m/s; east, north] the cloud shadows drift with (calm when the scenario has no ``[wind]``)."""
    sensors: SensorSpec = msgspec.field(default_factory=SensorSpec)
    """The relative-position sensor the same process simulates for every drone (``ranging_*``)."""

    def __post_init__(self) -> None:
        bad = sorted(role for role in self.roles.values() if role not in ROLES)
        if bad:
            raise ValueError(f"roles: unknown role {bad[0]!r}")
        _positive("camera.rate_hz", self.camera.rate_hz)
        check_imaging(self.imaging)


def _positive(name: str, value: float) -> None:
    if not value > 0.0:
        raise ValueError(f"{name}: must be > 0, got {value!r}")


def world_plan(scenario: Scenario) -> WorldPlan:
    """The flood model's inputs, with the scenario's folder made absolute (a plan may be read from anywhere)."""
    return WorldPlan(flood=dict(scenario.flood), seed=scenario.seed, source_dir=str(scenario.source_dir.resolve()))


def agent_plan(scenario: Scenario, vehicle_id: int, mode: str, mission: str | None = None) -> AgentPlan:
    """Vehicle ``vehicle_id``'s plan for a run in ``mode``; raises :class:`ScenarioError` for an unknown id or mode."""
    spec = next((v for v in scenario.vehicles if v.vehicle_id == vehicle_id), None)
    if spec is None:
        raise ScenarioError(f"--id {vehicle_id}: scenario {scenario.name} has vehicles 1..{len(scenario.vehicles)}")
    return AgentPlan(
        mission=mission or scenario.name, scenario=scenario.name, vehicle=spec, params=scenario.control_params(mode),
        control_rate_hz=scenario.control_rate_hz, altitude_m=scenario.altitude_m, camera=scenario.camera,
        home=scenario.home, seed=scenario.seed,
        start_delay_s=start_delays_s(tuple(v.vehicle_id for v in scenario.vehicles), scenario.start_jitter_s,
                                     scenario.seed)[scenario.vehicles.index(spec)],
    )


def fleet_plan(scenario: Scenario, mission: str | None = None) -> FleetPlan:
    """The whole fleet's plan for the mock PX4 process."""
    return FleetPlan(
        mission=mission or scenario.name, scenario=scenario.name, vehicles=scenario.vehicles, home=scenario.home,
        kinematics=scenario.kinematics, altitude_m=scenario.altitude_m, seed=scenario.seed,
        control_rate_hz=scenario.control_rate_hz, camera=scenario.camera, world=world_plan(scenario),
        wind=scenario.wind, sensors=scenario.sensors,
    )


def cameras_plan(scenario: Scenario, mission: str | None = None) -> CamerasPlan:
    """The camera renderer's plan."""
    return CamerasPlan(
        mission=mission or scenario.name, scenario=scenario.name, world=world_plan(scenario), camera=scenario.camera,
        roles={v.vehicle_id: v.role for v in scenario.vehicles}, imaging=scenario.imaging,
        wind_en_mps=mean_wind_en_mps(scenario), sensors=scenario.sensors,
    )

