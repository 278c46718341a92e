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
from mock_autopilot.dynamics_params import px4_params


class BackendKind(Enum):
    """Which vehicle dynamics a lockstep run flies (``--backend``)."""

    KINEMATIC = "kinematic"
    """The paper's holonomic point with PX4's limits and first-order response (fast)."""
    PX4 = "px4"
    """The sans-IO mock PX4 itself: MAVLink setpoints and commands, commander modes and failsafes."""


def make_backend(kind: BackendKind, scenario: Scenario) -> VehicleBackend:
    """The scenario's vehicles on the chosen backend; both read the scenario's ``[kinematics]`` (response time too)."""
    limits = scenario.kinematics
    if kind is BackendKind.PX4:
        from mock_autopilot.backends.px4 import Px4Backend
        from mock_autopilot.vehicle import VehicleConfig

        params = px4_params(limits, scenario.altitude_m)
        return Px4Backend([
            VehicleConfig(instance=i, has_gps=v.has_gps, pad_enu_m=v.pad_enu_m, home=scenario.home, params=params,
                          system_id=v.vehicle_id, response_time_s=limits.response_time_s)
            for i, v in enumerate(scenario.vehicles)
        ])
    return KinematicBackend(limits, len(scenario.vehicles))
