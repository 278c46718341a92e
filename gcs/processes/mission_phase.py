"""The ground station's mission phases as a pure state machine: what the station sees in, next phase out.

STARTING (children starting, agents connecting) -> TAKEOFF once every vehicle is heard on the GCS link and every
agent is up -> MISSION once every vehicle still flying is airborne in OFFBOARD (the flood clock starts) -> DONE when
the flood clock reaches the mission's duration. Start-up fails when it stalls (no new agent connected for the
start-up timeout), the take-off when its deadline in mission time passes. The shell
(:mod:`gcs.processes.ground_station`) gathers the observations and acts on the step: events, the start command,
the hold command at the end.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass


class MissionPhase(enum.StrEnum):
    STARTING = "starting"
    TAKEOFF = "takeoff"
    MISSION = "mission"
    DONE = "done"

    @property
    def in_flight(self) -> bool:
        """Vehicles are expected in the air: heartbeats and the mission clock are watched."""
        return self in (MissionPhase.TAKEOFF, MissionPhase.MISSION)


class PhaseFailure(enum.Enum):
    STARTUP_STALLED = "startup_stalled"
    TAKEOFF_TIMEOUT = "takeoff_timeout"


@dataclass(frozen=True)
class PhaseObservation:
    """What the station sees this loop: who is up, who is in OFFBOARD, the clocks [s]."""

    everyone_up: bool
    everyone_in_offboard: bool
    mission_t_s: float
    flood_t_s: float
    duration_s: float
    startup_idle_s: float
    """Wall time since start-up last made progress (the start, or the newest agent that connected)."""
    startup_timeout_s: float
    takeoff_timeout_s: float


@dataclass(frozen=True)
class PhaseState:
    phase: MissionPhase = MissionPhase.STARTING
    takeoff_deadline_s: float = math.inf
    """Mission time [s] by which every vehicle must be airborne in OFFBOARD."""


@dataclass(frozen=True)
class PhaseStep:
    state: PhaseState
    entered: MissionPhase | None = None
    """The phase entered this step, if any (the shell announces it)."""
    failure: PhaseFailure | None = None


def next_phase(state: PhaseState, seen: PhaseObservation) -> PhaseStep:
    """One step of the machine; at most one transition per call."""
    phase = state.phase
    if phase is MissionPhase.STARTING:
        if seen.everyone_up:
            return _enter(PhaseState(MissionPhase.TAKEOFF, seen.mission_t_s + seen.takeoff_timeout_s))
        if seen.startup_idle_s > seen.startup_timeout_s:
            return PhaseStep(state, failure=PhaseFailure.STARTUP_STALLED)
    elif phase is MissionPhase.TAKEOFF:
        if seen.everyone_in_offboard:
            return _enter(PhaseState(MissionPhase.MISSION, state.takeoff_deadline_s))
        if seen.mission_t_s > state.takeoff_deadline_s:
            return PhaseStep(state, failure=PhaseFailure.TAKEOFF_TIMEOUT)
    elif phase is MissionPhase.MISSION and seen.flood_t_s >= seen.duration_s:
        return _enter(PhaseState(MissionPhase.DONE, state.takeoff_deadline_s))
    return PhaseStep(state)


def _enter(state: PhaseState) -> PhaseStep:
    return PhaseStep(state, entered=state.phase)
