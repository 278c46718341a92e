"""The onboard flight sequence as a pure state machine: telemetry and commands in, next phase and action out.

The order is PX4's offboard recipe: connect, wait until the autopilot says it can arm, arm, take off (AUTO.TAKEOFF),
stream a first setpoint and switch to OFFBOARD, hover until the ground station starts the mission, then run the
control law. Any phase ends in LANDING or HOLDING on a ground-station command, a low battery or (during the mission) a ground
station that fell silent, and in LINK_LOST
when the autopilot falls silent (the agent then exits: it has nothing left to fly). When someone else takes the
vehicle out of OFFBOARD during the mission (a pilot, a failsafe), the agent stops commanding it (OVERRIDDEN), as a
PX4 offboard application should.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from comms.px4_mode_names import MAVSDK_OFFBOARD
from vehicle_agents.autopilot_link import AutopilotTelemetry


class Phase(enum.Enum):
    CONNECTING = "connecting"
    PREFLIGHT = "preflight"
    TAKING_OFF = "taking_off"
    STANDBY = "standby"
    """Airborne in OFFBOARD, hovering with a zero setpoint until the ground station says start."""
    MISSION = "mission"
    HOLDING = "holding"
    LANDING = "landing"
    OVERRIDDEN = "overridden"
    LINK_LOST = "link_lost"
    DONE = "done"


class Action(enum.Enum):
    NONE = "none"
    ARM = "arm"
    TAKEOFF = "takeoff"
    START_OFFBOARD = "start_offboard"
    HOVER = "hover"
    """Stream a zero velocity setpoint (keeps the offboard proof of life)."""
    FLY = "fly"
    """Run the control law and stream its setpoint."""
    HOLD = "hold"
    LAND = "land"
    EXIT = "exit"


class Command(enum.Enum):
    """What the ground station may ask of an agent (MissionCommand on Zenoh)."""

    START = "start"
    HOLD = "hold"
    LAND = "land"
    STOP = "stop"
    """End the agent process (after landing or when the mission is over)."""


@dataclass(frozen=True)
class PhaseLimits:
    takeoff_altitude_m: float = 10.0
    takeoff_reached_fraction: float = 0.9
    link_timeout_s: float = 2.0
    """Wall-clock silence after which the autopilot of a flying vehicle counts as lost (PX4 heartbeat is 1 Hz,
    telemetry tens of Hz; SPEC §7 wants the loss noticed within 3 s)."""
    ground_link_timeout_s: float = 10.0
    """The same before take-off: on the ground nothing needs protecting, and a machine busy starting a whole
    fleet can delay telemetry by seconds."""
    low_battery_fraction: float = 0.15
    gcs_link_timeout_s: float = 5.0
    """Wall seconds without a ground-station command (it repeats them twice a second) after which a flying agent
    holds position: the swarm should not keep working for a ground station that no longer watches it."""


@dataclass(frozen=True)
class PhaseInputs:
    telemetry: AutopilotTelemetry
    link_silence_s: float
    """Wall seconds since the autopilot's newest message; NaN before the first."""
    command: Command | None = None
    command_age_s: float | None = None
    """Wall seconds since the last ground-station command; None before the first (no ground station yet)."""


def next_phase(phase: Phase, inputs: PhaseInputs, limits: PhaseLimits) -> tuple[Phase, Action]:
    """One decision of the onboard sequence; called every control period. Pure."""
    tel = inputs.telemetry
    if phase in (Phase.LINK_LOST, Phase.DONE):
        return phase, Action.EXIT
    timeout_s = limits.ground_link_timeout_s if phase is Phase.PREFLIGHT else limits.link_timeout_s
    if phase is not Phase.CONNECTING and inputs.link_silence_s > timeout_s:
        return Phase.LINK_LOST, Action.EXIT
    if inputs.command is Command.STOP:
        return Phase.DONE, Action.EXIT
    flying_phases = (Phase.TAKING_OFF, Phase.STANDBY, Phase.MISSION)
    if phase in flying_phases and tel.in_air:
        if inputs.command is Command.LAND or tel.battery_fraction < limits.low_battery_fraction:
            return Phase.LANDING, Action.LAND
        if inputs.command is Command.HOLD:
            return Phase.HOLDING, Action.HOLD
        if phase is Phase.MISSION and inputs.command_age_s is not None and inputs.command_age_s > limits.gcs_link_timeout_s:
            return Phase.HOLDING, Action.HOLD
    if phase is Phase.CONNECTING:
        return (Phase.PREFLIGHT, Action.NONE) if not math.isnan(inputs.link_silence_s) else (phase, Action.NONE)
    if phase is Phase.PREFLIGHT:
        if tel.armed and tel.in_air:
            return Phase.TAKING_OFF, Action.NONE
        if tel.armed:
            return Phase.TAKING_OFF, Action.TAKEOFF
        return (phase, Action.ARM) if tel.ready_to_arm else (phase, Action.NONE)
    if phase is Phase.TAKING_OFF:
        altitude_m = -tel.position_ned_m[2]
        if tel.flight_mode == MAVSDK_OFFBOARD:
            return Phase.STANDBY, Action.HOVER
        if tel.in_air and altitude_m >= limits.takeoff_reached_fraction * limits.takeoff_altitude_m:
            return phase, Action.START_OFFBOARD
        if not tel.armed:
            return Phase.PREFLIGHT, Action.NONE
        return phase, Action.NONE
    if phase in (Phase.STANDBY, Phase.MISSION) and tel.flight_mode != MAVSDK_OFFBOARD:
        return Phase.OVERRIDDEN, Action.NONE
    if phase is Phase.STANDBY:
        return (Phase.MISSION, Action.FLY) if inputs.command is Command.START else (phase, Action.HOVER)
    if phase is Phase.MISSION:
        return phase, Action.FLY
    if phase is Phase.LANDING and not tel.armed and not tel.in_air:
        return Phase.DONE, Action.EXIT
    return phase, Action.NONE
