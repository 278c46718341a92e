"""The agent's estimate of mission time under a speed factor."""

from __future__ import annotations

import pytest

from vehicle_agents.mission_clock import MissionClock


class FakeWall:
    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def test_runs_at_speed_and_jumps_forward_to_late_stamps() -> None:
    wall = FakeWall()
    clock = MissionClock(4.0, wall)
    wall.t += 1.0
    assert clock.now_s() == pytest.approx(4.0)
    clock.observe(50.0)
    assert clock.now_s() == pytest.approx(50.0)
    wall.t += 0.5
    assert clock.now_s() == pytest.approx(52.0)
    clock.observe(60.0)
    assert clock.now_s() == pytest.approx(60.0)


def test_never_runs_backwards_on_early_stamps() -> None:
    wall = FakeWall()
    clock = MissionClock(1.0, wall)
    clock.observe(10.0)
    wall.t += 1.0
    before = clock.now_s()
    clock.observe(5.0)
    assert clock.now_s() >= before
    wall.t += 1.0
    assert clock.now_s() < before + 1.0 + 1e-9


def test_wall_period_and_bad_speed() -> None:
    assert MissionClock(4.0).wall_period_s(0.05) == pytest.approx(0.0125)
    with pytest.raises(ValueError, match="speed"):
        MissionClock(0.0)
