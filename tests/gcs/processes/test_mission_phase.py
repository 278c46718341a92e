"""The ground station's mission phases as a pure machine: transitions, failures, and nothing skipped."""

from __future__ import annotations

import math
from dataclasses import replace

from gcs.processes.mission_phase import (
    MissionPhase,
    PhaseFailure,
    PhaseObservation,
    PhaseState,
    next_phase,
)

NOTHING = PhaseObservation(everyone_up=False, everyone_in_offboard=False, mission_t_s=0.0, flood_t_s=0.0,
                           duration_s=60.0, startup_idle_s=0.0, startup_timeout_s=30.0, takeoff_timeout_s=90.0)


def test_starting_waits_then_takes_off_with_a_deadline_in_mission_time() -> None:
    step = next_phase(PhaseState(), NOTHING)
    assert step.state.phase is MissionPhase.STARTING and step.entered is None and step.failure is None
    step = next_phase(PhaseState(), replace(NOTHING, everyone_up=True, mission_t_s=5.0))
    assert step.entered is MissionPhase.TAKEOFF and step.state.takeoff_deadline_s == 95.0


def test_startup_fails_only_when_it_stalls() -> None:
    assert next_phase(PhaseState(), replace(NOTHING, startup_idle_s=30.0)).failure is None
    assert next_phase(PhaseState(), replace(NOTHING, startup_idle_s=30.1)).failure is PhaseFailure.STARTUP_STALLED
    # everyone up wins over a stall seen in the same loop
    assert next_phase(PhaseState(), replace(NOTHING, everyone_up=True, startup_idle_s=99.0)).failure is None


def test_takeoff_to_mission_and_its_timeout() -> None:
    takeoff = PhaseState(MissionPhase.TAKEOFF, 95.0)
    assert next_phase(takeoff, replace(NOTHING, mission_t_s=95.0)).failure is None
    assert next_phase(takeoff, replace(NOTHING, mission_t_s=95.1)).failure is PhaseFailure.TAKEOFF_TIMEOUT
    step = next_phase(takeoff, replace(NOTHING, everyone_in_offboard=True, mission_t_s=200.0))
    assert step.entered is MissionPhase.MISSION and step.failure is None
    # everyone_up alone does not move TAKEOFF on: one transition at a time, by its own condition
    assert next_phase(takeoff, replace(NOTHING, everyone_up=True)).state == takeoff


def test_mission_ends_when_the_flood_clock_reaches_the_duration() -> None:
    mission = PhaseState(MissionPhase.MISSION, 95.0)
    assert next_phase(mission, replace(NOTHING, flood_t_s=59.9)).entered is None
    step = next_phase(mission, replace(NOTHING, flood_t_s=60.0))
    assert step.entered is MissionPhase.DONE and step.state.phase is MissionPhase.DONE
    assert next_phase(step.state, replace(NOTHING, flood_t_s=math.inf)).entered is None


def test_in_flight_phases() -> None:
    assert [p for p in MissionPhase if p.in_flight] == [MissionPhase.TAKEOFF, MissionPhase.MISSION]
