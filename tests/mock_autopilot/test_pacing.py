"""The paced clock's state machine: services, then agents, then the next gate; timeouts, rejoining, leaving."""

from __future__ import annotations

import pytest

from mock_autopilot.clock import SimClock
from mock_autopilot.pacing import CLOCK_REPEAT_WALL_S, PaceActionKind, Pacer, PaceStage

PERIOD_S = 0.05


def kinds(actions) -> list[PaceActionKind]:  # noqa: ANN001
    return [a.kind for a in actions]


def joined(pacer: Pacer, wall_s: float = 0.0) -> Pacer:
    """A pacer that has heard the cameras, the radio and agents 1 and 2 acknowledge tick 0."""
    for name in ("cameras", "radio", "1", "2"):
        pacer.on_ack(name, 0.0, False, wall_s)
    return pacer


def test_a_tick_waits_for_the_services_then_for_every_agent_then_moves_the_gate() -> None:
    pacer = joined(Pacer(PERIOD_S, agent_timeout_s=2.0))
    assert pacer.step(clock_held=False, wall_s=0.01) == []
    assert kinds(pacer.step(clock_held=True, wall_s=0.02)) == [PaceActionKind.PUBLISH_TRUTH]
    assert sorted(pacer.waiting_for()) == ["cameras", "radio"]
    pacer.on_ack("cameras", PERIOD_S, False, 0.03)
    assert pacer.step(True, 0.03) == []
    pacer.on_ack("radio", PERIOD_S, False, 0.04)
    actions = pacer.step(True, 0.04)
    assert kinds(actions) == [PaceActionKind.PUBLISH_CLOCK] and actions[0].t_s == pytest.approx(PERIOD_S)
    assert sorted(pacer.waiting_for()) == ["1", "2"]
    pacer.on_ack("1", PERIOD_S, False, 0.05)
    assert pacer.step(True, 0.05) == []
    pacer.on_ack("2", PERIOD_S, False, 0.09)
    actions = pacer.step(True, 0.09)
    assert kinds(actions) == [PaceActionKind.SET_GATE] and actions[0].t_s == pytest.approx(2 * PERIOD_S)
    assert pacer.stage is PaceStage.ADVANCING
    assert pacer.records["2"].max_wait_wall_s == pytest.approx(0.05)


def test_gates_are_whole_multiples_of_the_period() -> None:
    pacer = Pacer(0.1, agent_timeout_s=2.0)
    for _ in range(1000):
        pacer.step(True, 0.0)
        pacer.step(True, 0.0)
    assert pacer.gate_s == pacer.tick * 0.1


def test_an_agent_silent_past_the_timeout_is_left_behind_and_rejoins_when_it_catches_up() -> None:
    pacer = joined(Pacer(PERIOD_S, agent_timeout_s=2.0))
    pacer.step(True, 0.0)
    for name in ("cameras", "radio", "1"):
        pacer.on_ack(name, PERIOD_S, False, 0.01)
    pacer.step(True, 0.01)
    assert pacer.waiting_for() == ["2"]
    assert kinds(pacer.step(True, 1.9)) == [PaceActionKind.PUBLISH_CLOCK], "repeated, nobody left behind yet"
    actions = pacer.step(True, 2.2)
    assert kinds(actions) == [PaceActionKind.LEFT_BEHIND, PaceActionKind.SET_GATE]
    assert actions[0].participant == "2" and pacer.records["2"].times_left_behind == 1
    pacer.step(True, 2.3)
    for name in ("cameras", "radio"):
        pacer.on_ack(name, 2 * PERIOD_S, False, 2.3)
    pacer.step(True, 2.3)
    assert pacer.waiting_for() == ["1"], "a left-behind agent is not waited for"
    rejoined = pacer.on_ack("2", 2 * PERIOD_S, False, 2.4)
    assert kinds(rejoined) == [PaceActionKind.REJOINED] and not pacer.records["2"].left_behind


def test_a_leaving_or_departed_agent_is_not_waited_for() -> None:
    pacer = joined(Pacer(PERIOD_S, agent_timeout_s=2.0))
    pacer.on_ack("1", 0.0, True, 0.0)
    pacer.on_departed("2")
    pacer.step(True, 0.0)
    pacer.on_ack("cameras", PERIOD_S, False, 0.0)
    pacer.on_ack("radio", PERIOD_S, False, 0.0)
    assert kinds(pacer.step(True, 0.0)) == [PaceActionKind.PUBLISH_CLOCK, PaceActionKind.SET_GATE]


def test_the_clock_tick_is_repeated_while_agents_are_awaited() -> None:
    pacer = joined(Pacer(PERIOD_S, agent_timeout_s=5.0))
    pacer.step(True, 0.0)
    pacer.on_ack("cameras", PERIOD_S, False, 0.0)
    pacer.on_ack("radio", PERIOD_S, False, 0.0)
    assert kinds(pacer.step(True, 0.0)) == [PaceActionKind.PUBLISH_CLOCK]
    assert pacer.step(True, CLOCK_REPEAT_WALL_S / 2) == []
    assert kinds(pacer.step(True, CLOCK_REPEAT_WALL_S + 0.01)) == [PaceActionKind.PUBLISH_CLOCK]


def test_a_free_clock_only_counts_ticks() -> None:
    pacer = Pacer(PERIOD_S, agent_timeout_s=2.0, paced=False)
    for k in range(21):
        pacer.on_ack("7", k * PERIOD_S, False, 0.0)
    assert pacer.step(True, 100.0) == []
    assert pacer.records["7"].ticks == 21
    assert pacer.records["7"].rate_hz() == pytest.approx(1.0 / PERIOD_S)


def test_bad_periods_and_timeouts_are_refused() -> None:
    with pytest.raises(ValueError):
        Pacer(0.0, 2.0)
    with pytest.raises(ValueError):
        Pacer(0.05, 0.0)


class FakeWall:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def test_the_gated_clock_stands_at_its_gate_and_catches_up_when_it_moves() -> None:
    wall = FakeWall()
    clock = SimClock(2.0, wall_clock=wall, gate_s=1.0)
    wall.t = 0.25
    assert clock.now_s() == pytest.approx(0.5) and not clock.held()
    wall.t = 3.0
    assert clock.now_s() == 1.0 and clock.held()
    clock.set_gate(1.5)
    assert clock.now_s() == 1.5, "time lost waiting is caught up at once, up to the new gate"
    clock.set_gate(0.2)
    assert clock.now_s() == 1.5, "a gate never sends time backwards"


def test_a_free_clock_has_no_gate() -> None:
    wall = FakeWall()
    clock = SimClock(3.0, wall_clock=wall)
    wall.t = 10.0
    assert clock.now_s() == pytest.approx(30.0) and not clock.held()


def test_the_cameras_and_the_radio_are_waited_for_however_slow() -> None:
    pacer = joined(Pacer(PERIOD_S, agent_timeout_s=2.0))
    pacer.step(True, 0.0)
    pacer.on_ack("radio", PERIOD_S, False, 0.0)
    assert PaceActionKind.LEFT_BEHIND not in kinds(pacer.step(True, 60.0))
    assert pacer.waiting_for() == ["cameras"]
    pacer.on_ack("cameras", PERIOD_S, False, 61.0)
    assert kinds(pacer.step(True, 61.0)) == [PaceActionKind.PUBLISH_CLOCK]
    assert pacer.records["cameras"].max_wait_wall_s == pytest.approx(61.0)
