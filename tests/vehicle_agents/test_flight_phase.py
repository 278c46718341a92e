"""The onboard sequence, decided without sockets."""

from __future__ import annotations

import math
from dataclasses import replace

from vehicle_agents.autopilot_link import AutopilotTelemetry
from vehicle_agents.flight_phase import Action, Command, Phase, PhaseInputs, PhaseLimits, next_phase

LIMITS = PhaseLimits(takeoff_altitude_m=10.0, link_timeout_s=1.5, low_battery_fraction=0.15)
FRESH = AutopilotTelemetry(last_message_monotonic_s=100.0, ready_to_arm=True)


def step(phase: Phase, tel: AutopilotTelemetry, command: Command | None = None, now_s: float = 100.1) -> tuple[Phase, Action]:
    silence_s = math.nan if tel.last_message_monotonic_s == 0.0 else now_s - tel.last_message_monotonic_s
    return next_phase(phase, PhaseInputs(telemetry=tel, link_silence_s=silence_s, command=command), LIMITS)


def test_full_sequence_reaches_mission_only_after_start() -> None:
    phase, action = step(Phase.CONNECTING, FRESH)
    assert (phase, action) == (Phase.PREFLIGHT, Action.NONE)
    assert step(phase, FRESH) == (Phase.PREFLIGHT, Action.ARM)
    armed = replace(FRESH, armed=True)
    phase, action = step(Phase.PREFLIGHT, armed)
    assert (phase, action) == (Phase.TAKING_OFF, Action.TAKEOFF)
    climbing = replace(armed, in_air=True, flight_mode="TAKEOFF", position_ned_m=(0.0, 0.0, -5.0))
    assert step(phase, climbing) == (Phase.TAKING_OFF, Action.NONE)
    at_altitude = replace(climbing, flight_mode="HOLD", position_ned_m=(0.0, 0.0, -9.5))
    assert step(phase, at_altitude) == (Phase.TAKING_OFF, Action.START_OFFBOARD)
    offboard = replace(at_altitude, flight_mode="OFFBOARD")
    phase, action = step(phase, offboard)
    assert (phase, action) == (Phase.STANDBY, Action.HOVER)
    assert step(phase, offboard) == (Phase.STANDBY, Action.HOVER)
    assert step(phase, offboard, Command.START) == (Phase.MISSION, Action.FLY)
    assert step(Phase.MISSION, offboard) == (Phase.MISSION, Action.FLY)


def test_not_ready_to_arm_waits() -> None:
    assert step(Phase.PREFLIGHT, replace(FRESH, ready_to_arm=False)) == (Phase.PREFLIGHT, Action.NONE)


def test_silent_autopilot_is_link_lost_and_exits() -> None:
    tel = replace(FRESH, armed=True, in_air=True, flight_mode="OFFBOARD")
    assert step(Phase.MISSION, tel, now_s=101.0) == (Phase.MISSION, Action.FLY)
    assert step(Phase.MISSION, tel, now_s=102.0) == (Phase.LINK_LOST, Action.EXIT)


def test_connecting_does_not_time_out() -> None:
    assert step(Phase.CONNECTING, AutopilotTelemetry(), now_s=1000.0) == (Phase.CONNECTING, Action.NONE)


def test_low_battery_lands_and_land_command_lands() -> None:
    flying = replace(FRESH, armed=True, in_air=True, flight_mode="OFFBOARD")
    assert step(Phase.MISSION, replace(flying, battery_fraction=0.1)) == (Phase.LANDING, Action.LAND)
    assert step(Phase.STANDBY, flying, Command.LAND) == (Phase.LANDING, Action.LAND)
    assert step(Phase.MISSION, flying, Command.HOLD) == (Phase.HOLDING, Action.HOLD)


def test_landing_ends_when_disarmed_on_ground() -> None:
    landing = replace(FRESH, armed=True, in_air=True, flight_mode="LAND")
    assert step(Phase.LANDING, landing) == (Phase.LANDING, Action.NONE)
    landed = replace(landing, armed=False, in_air=False)
    assert step(Phase.LANDING, landed) == (Phase.DONE, Action.EXIT)


def test_mode_taken_away_stops_commanding() -> None:
    hold = replace(FRESH, armed=True, in_air=True, flight_mode="HOLD")
    assert step(Phase.MISSION, hold) == (Phase.OVERRIDDEN, Action.NONE)
    assert step(Phase.OVERRIDDEN, hold) == (Phase.OVERRIDDEN, Action.NONE)


def test_stop_command_exits_from_anywhere() -> None:
    assert step(Phase.PREFLIGHT, FRESH, Command.STOP) == (Phase.DONE, Action.EXIT)


def test_on_the_ground_the_link_gets_more_patience() -> None:
    tel = replace(FRESH, ready_to_arm=False)
    assert step(Phase.PREFLIGHT, tel, now_s=105.0) == (Phase.PREFLIGHT, Action.NONE)
    assert step(Phase.PREFLIGHT, tel, now_s=111.0) == (Phase.LINK_LOST, Action.EXIT)


def test_silent_ground_station_makes_a_flying_agent_hold() -> None:
    flying = replace(FRESH, armed=True, in_air=True, flight_mode="OFFBOARD")
    inputs = PhaseInputs(telemetry=flying, link_silence_s=0.1, command=Command.START, command_age_s=1.0)
    assert next_phase(Phase.MISSION, inputs, LIMITS) == (Phase.MISSION, Action.FLY)
    silent = replace(inputs, command_age_s=6.0)
    assert next_phase(Phase.MISSION, silent, LIMITS) == (Phase.HOLDING, Action.HOLD)
    never_heard = replace(inputs, command=None, command_age_s=None)
    assert next_phase(Phase.STANDBY, never_heard, LIMITS) == (Phase.STANDBY, Action.HOVER)
