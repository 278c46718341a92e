"""Engine health and safety are separate verdicts, each from its own evidence."""

from __future__ import annotations

import math

from comms.messages import CameraStats, PaceReport, ParticipantPace
from gcs.processes.run_verdict import EngineHealth, engine_verdict, safety_verdict


def participant(name: str, ticks: int, span_s: float, times_left_behind: int = 0) -> ParticipantPace:
    return ParticipantPace(participant=name, ticks=ticks, first_t_s=1.0, last_t_s=1.0 + span_s, max_wait_wall_s=0.02,
                           times_left_behind=times_left_behind)


def report(*participants: ParticipantPace) -> PaceReport:
    return PaceReport(t_s=61.0, wall_s=80.0, paced=True, real_time_factor=0.76, recent_real_time_factor=0.8,
                      held_wall_s=12.0, participants=list(participants))


CAMERAS_OK = CameraStats(t_s=61.0, frames_sent=4800, frame_rate_hz=9.98, nominal_rate_hz=10.0)


def test_every_agent_at_its_rate_and_cameras_at_theirs_is_complete() -> None:
    verdict = engine_verdict(report(participant("1", 1201, 60.0), participant("2", 1201, 60.0)), CAMERAS_OK, [1, 2],
                             20.0, "paced")
    assert verdict.health is EngineHealth.COMPLETE, verdict.reasons
    assert verdict.agent_rate_min_hz == 20.0 and "0.76x" in verdict.text()


def test_an_agent_below_its_rate_degrades_the_engine_and_is_named() -> None:
    verdict = engine_verdict(report(participant("1", 1201, 60.0), participant("2", 700, 60.0)), CAMERAS_OK, [1, 2],
                             20.0, "free")
    assert verdict.health is EngineHealth.DEGRADED
    assert "1 agent below 95% of the 20 Hz control rate (slowest 11.7 Hz): 2" in verdict.text()


def test_left_behind_missing_agents_and_slow_cameras_are_each_reasons() -> None:
    slow_cameras = CameraStats(t_s=61.0, frames_sent=2000, frame_rate_hz=4.1, nominal_rate_hz=10.0)
    verdict = engine_verdict(report(participant("1", 1201, 60.0, times_left_behind=1)), slow_cameras, [1, 2], 20.0,
                             "paced")
    assert verdict.health is EngineHealth.DEGRADED
    assert verdict.left_behind == ("1",)
    text = verdict.text()
    assert "agent 2 never reported a tick" in text and "left behind by the paced clock: 1" in text
    assert "cameras at 4.10 Hz of 10 Hz" in text


def test_no_report_at_all_is_degraded_not_complete() -> None:
    verdict = engine_verdict(None, CAMERAS_OK, [1], 20.0, "paced")
    assert verdict.health is EngineHealth.DEGRADED and math.isnan(verdict.real_time_factor)


def test_safety_counts_failsafes_and_near_misses_whatever_the_engine_did() -> None:
    safety = safety_verdict({"near_miss_pairs": 11, "min_pairwise_distance_m": 0.02},
                            ["vehicle 3: Failsafe: offboard lost, POSCTL"])
    assert safety.as_json() == {"failsafes": ["vehicle 3: Failsafe: offboard lost, POSCTL"], "failsafe_count": 1,
                                "near_miss_pairs": 11, "closest_approach_m": 0.02}
    assert safety.text() == "safety: 1 failsafe, 11 pairs closer than 1 m, closest approach 0.02 m"
