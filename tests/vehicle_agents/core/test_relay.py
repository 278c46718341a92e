"""Multi-hop relay: the hop limit, ageing, the byte budget, fair rotation, and unpacking at the receiver (pure)."""

from __future__ import annotations

from comms.messages import NeighbourState, encode
from vehicle_agents.core.neighbours import Inbox, heard_after
from vehicle_agents.core.relay import relay_copies, unpacked


def _state(vid: int, t_s: float, seq: int = 1, hops: int = 0, edge_points: int = 0) -> NeighbourState:
    return NeighbourState(sender_id=vid, role="boundary", seq=seq, t_s=t_s, position_en_m=(float(vid), 0.0),
                          altitude_m=10.0, hops=hops, edge_points_en_m=[(float(k), 1.0) for k in range(edge_points)])


def test_hop_limit_counts_hops_from_the_origin() -> None:
    table = {2: _state(2, 5.0), 3: _state(3, 5.0, hops=1), 4: _state(4, 5.0, hops=2)}
    copies = relay_copies(table, own_id=1, t_s=5.0, seq=1, max_hops=2, max_age_s=1.0, budget_bytes=10_000)
    assert sorted((c.sender_id, c.hops) for c in copies) == [(2, 1), (3, 2)]
    assert all(not c.relayed for c in copies)
    assert relay_copies(table, 1, 5.0, 1, max_hops=0, max_age_s=1.0, budget_bytes=10_000) == []


def test_stale_states_age_out_by_their_origin_time() -> None:
    table = {2: _state(2, 3.9), 3: _state(3, 4.1), 1: _state(1, 5.0)}
    copies = relay_copies(table, own_id=1, t_s=5.0, seq=1, max_hops=3, max_age_s=1.0, budget_bytes=10_000)
    assert [c.sender_id for c in copies] == [3]  # 2 is 1.1 s old; 1 is oneself


def test_byte_budget_bounds_every_message_and_rotation_passes_everyone_on() -> None:
    table = {vid: _state(vid, 5.0, edge_points=24) for vid in range(2, 14)}
    one_size = len(encode(relay_copies(table, 1, 5.0, 1, 3, 1.0, 10_000)[0]))
    budget = 3 * one_size + one_size // 2
    seen: set[int] = set()
    for seq in range(40):
        copies = relay_copies(table, 1, 5.0, seq, 3, 1.0, budget)
        assert sum(len(encode(c)) for c in copies) <= budget and len(copies) == 3
        seen |= {c.sender_id for c in copies}
    assert seen == set(range(2, 14))


def test_receiver_files_relayed_copies_like_direct_messages_newest_seq_wins() -> None:
    direct = _state(2, 5.0, seq=10)
    carrier = NeighbourState(sender_id=2, role="follower", seq=11, t_s=5.0, position_en_m=(0.0, 0.0), altitude_m=10.0,
                             relayed=[_state(3, 4.9, seq=7, hops=1), _state(4, 4.8, seq=3, hops=2)])
    table, _ = heard_after({}, frozenset(), Inbox(states=[direct]), own_id=1, t_s=5.0, timeout_s=3.0)
    table, _ = heard_after(table, frozenset(), Inbox(states=unpacked([carrier])), own_id=1, t_s=5.05, timeout_s=3.0)
    assert sorted(table) == [2, 3, 4] and table[3].hops == 1 and table[4].t_s == 4.8
    older_copy = NeighbourState(sender_id=5, role="follower", seq=1, t_s=5.1, position_en_m=(0.0, 0.0),
                                altitude_m=10.0, relayed=[_state(3, 4.5, seq=6, hops=2)])
    table, _ = heard_after(table, frozenset(), Inbox(states=unpacked([older_copy])), 1, 5.1, 3.0)
    assert table[3].seq == 7
