"""Which vehicle dynamics a lockstep run flies (``--backend kinematic|px4``), built from the scenario.

Both backends read the scenario's ``[kinematics]``, ``response_time_s`` included, so the choice changes the fidelity
of the vehicle (a point with PX4's limits, or the mock PX4 with its MAVLink front end, modes and failsafes), never
its dynamics parameters.
"""

from __future__ import annotations

from enum import Enum

from gcs.scenario import Scenario
from mock_autopilot.backends.interface import VehicleBackend
from mock_autopilot.backends.kinematic import KinematicBackend
from mock_autopilot.weather_model import Weather


def scenario_weather(scenario: Scenario, seed: int | None = None) -> Weather:
    """The scenario's ``[wind]`` and ``[sensors]`` at its nominal altitude, drawn from ``seed`` (default its own)."""
    return Weather(scenario.wind, scenario.sensors, scenario.seed if seed is None else seed, scenario.altitude_m)


class BackendKind(Enum):
    """Which vehicle dynamics a lockstep run flies (``--backend``)."""

    KINEMATIC = "kinematic"
    """The paper's holonomic point with PX4's limits and first-order response (fast)."""
    PX4 = "px4"
    """The sans-IO mock PX4 itself: MAVLink setpoints and commands, commander modes and failsafes."""


def make_backend(kind: BackendKind, scenario: Scenario, seed: int | None = None) -> VehicleBackend:
    """The scenario's vehicles on the chosen backend; both read the scenario's ``[kinematics]`` (response time too)
    and fly in its weather."""
    limits = scenario.kinematics
    weather = scenario_weather(scenario, seed)
    ids = [v.vehicle_id for v in scenario.vehicles]
    gps = [v.has_gps for v in scenario.vehicles]
    if kind is BackendKind.PX4:
        from mock_autopilot.backends.px4 import Px4Backend, px4_vehicle_configs

        return Px4Backend(px4_vehicle_configs(limits, scenario.altitude_m, [v.pad_enu_m for v in scenario.vehicles],
                                              has_gps=gps, home=scenario.home, system_ids=ids,
                                              weather=weather))
    return KinematicBackend(limits, len(scenario.vehicles), weather, ids, gps)
