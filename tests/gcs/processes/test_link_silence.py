"""A starved ground station does not call its fleet lost; a silent vehicle is still lost."""

from __future__ import annotations

import math

from gcs.processes.link_silence import OWN_STALL_S, SilenceJudge


def _passes(judge: SilenceJudge, start_s: float, end_s: float, ages_at) -> list:  # noqa: ANN001
    verdicts, t = [], start_s
    while t <= end_s + 1e-9:
        verdicts.append((t, judge.step(t, ages_at(t))))
        t = round(t + 0.05, 6)
    return verdicts


def test_a_vehicle_silent_past_the_bound_is_lost_and_comes_back() -> None:
    judge = SilenceJudge(lost_after_s=2.0)
    last_beat = {1: 0.0, 2: 0.0}

    def ages(t: float) -> dict[int, float]:
        last_beat[1] = math.floor(t)  # vehicle 1 beats every second; vehicle 2 fell silent at 0
        return {vid: t - beat for vid, beat in last_beat.items()}

    verdicts = _passes(judge, 0.0, 3.0, ages)
    lost_at = [t for t, v in verdicts if 2 in v.lost]
    assert lost_at and 2.0 < lost_at[0] <= 2.05 + 1e-9
    assert all(1 not in v.lost for _, v in verdicts)
    assert judge.step(3.05, {1: 0.05, 2: 0.0}).back == (2,)


def test_after_its_own_stall_the_station_reads_its_backlog_before_judging() -> None:
    """The loop did not run from 10 s to 12.5 s; the heartbeats sent meanwhile are read over the next passes (the
    first pass after the stall has read only vehicle 1's). Nobody is lost, and the stall is reported."""
    judge = SilenceJudge(lost_after_s=2.0)
    assert judge.step(10.0, {1: 0.1, 2: 0.1}).lost == ()
    first = judge.step(12.5, {1: 0.0, 2: 2.6})
    assert first.lost == () and first.own_stall_s == 2.5
    assert judge.step(12.55, {1: 0.05, 2: 0.0}).lost == ()
    assert judge.silent == set()


def test_a_vehicle_still_silent_after_the_grace_is_lost() -> None:
    judge = SilenceJudge(lost_after_s=2.0)
    judge.step(10.0, {1: 0.1, 2: 0.1})
    assert judge.step(12.5, {1: 0.0, 2: 2.6}).lost == ()
    assert judge.step(12.5 + OWN_STALL_S / 2, {1: 0.1, 2: 2.85}).lost == ()
    assert judge.step(12.5 + OWN_STALL_S, {1: 0.2, 2: 3.1}).lost == (2,)


def test_before_take_off_nothing_is_judged() -> None:
    judge = SilenceJudge(lost_after_s=2.0)
    assert judge.step(0.0, {1: math.inf}, judging=False).lost == ()
    assert judge.step(5.0, {1: math.inf}, judging=True).lost == ()  # the 5 s gap was the loop's own
    assert judge.step(5.5, {1: math.inf}).lost == (1,)


def test_the_vehicles_that_only_looked_silent_are_named() -> None:
    judge = SilenceJudge(lost_after_s=2.0)
    judge.step(10.0, {1: 0.1, 2: 0.1, 3: 0.1})
    verdict = judge.step(12.5, {1: 0.0, 2: 2.6, 3: 2.6})
    assert verdict.spared == (2, 3) and verdict.lost == ()
    assert judge.step(12.55, {1: 0.05, 2: 0.0, 3: 0.0}).spared == ()
