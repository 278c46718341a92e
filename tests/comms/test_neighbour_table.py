"""NeighbourTable: newest seq wins, staleness after three periods, liveliness deaths, leaving."""

from __future__ import annotations

from comms.messages import FLAG_LEAVING, NeighbourState
from comms.neighbour_table import NeighbourTable


def _s(vid: int, seq: int, t_s: float, flags: int = 0) -> NeighbourState:
    return NeighbourState(sender_id=vid, role="boundary", seq=seq, t_s=t_s, position_en_m=(float(vid), 0.0), altitude_m=10.0, flags=flags)


def test_newest_seq_wins_and_own_ignored() -> None:
    t = NeighbourTable(own_id=0, period_s=0.05)
    assert not t.heard(_s(0, 1, 0.0), 0.0)
    assert t.heard(_s(1, 5, 0.0), 0.0)
    assert not t.heard(_s(1, 4, 0.01), 0.01)  # reordered by jitter
    assert t.get(1).state.seq == 5 and t.ignored_old == 1
    assert t.heard(_s(1, 6, 0.05), 0.05)
    assert [e.event for e in t.take_events()] == ["joined"]


def test_stale_after_three_periods_then_rejoins() -> None:
    t = NeighbourTable(own_id=None, period_s=0.05, stale_periods=3)
    t.heard(_s(2, 1, 0.0), 0.0)
    assert t.expire(0.149) == []
    stale = t.expire(0.151)
    assert [(e.vehicle_id, e.event) for e in stale] == [(2, "stale")]
    assert t.neighbours() == [] and t.stale_ids == [2]
    t.heard(_s(2, 2, 0.3), 0.3)
    assert t.fresh_ids == [2]
    assert [e.event for e in t.take_events()] == ["joined", "stale", "rejoined"]


def test_liveliness_death_drops_at_once_and_blocks_late_messages() -> None:
    t = NeighbourTable(own_id=0)
    t.heard(_s(3, 1, 0.0), 0.0)
    t.liveliness(3, False, 0.01)
    assert t.fresh_ids == [] and t.dead_ids == [3]
    assert not t.heard(_s(3, 2, 0.02), 0.02)  # a message still in flight in the radio
    assert t.ignored_dead == 1
    t.liveliness(3, True, 1.0)  # restarted process
    assert t.heard(_s(3, 0, 1.0), 1.0)  # seq restarted from zero
    assert [e.event for e in t.take_events()] == ["joined", "dead", "alive", "joined"]


def test_restart_with_lower_seq_accepted_after_a_gap() -> None:
    t = NeighbourTable(period_s=0.05)
    t.heard(_s(4, 100, 1.0), 1.0)
    assert not t.heard(_s(4, 1, 1.05), 1.05)
    assert t.heard(_s(4, 1, 1.5), 1.5)


def test_leaving_flag_removes_neighbour() -> None:
    t = NeighbourTable()
    t.heard(_s(5, 1, 0.0), 0.0)
    t.heard(_s(5, 2, 0.05, flags=FLAG_LEAVING), 0.05)
    assert t.fresh_ids == [] and 5 in t.dead_ids
    assert t.take_events()[-1].event == "left"


def test_neighbours_sorted_with_age() -> None:
    t = NeighbourTable()
    t.heard(_s(9, 1, 0.9), 1.0)
    t.heard(_s(2, 1, 0.95), 1.0)
    ns = t.neighbours(1.0)
    assert [n.vehicle_id for n in ns] == [2, 9]
    assert abs(ns[1].age_s(1.0) - 0.1) < 1e-9
