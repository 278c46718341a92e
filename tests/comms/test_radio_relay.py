"""RadioRelay (the emulator's logic without Zenoh): truth-based gating, rejection, delays, link counters."""

from __future__ import annotations

import msgspec
import numpy as np

from comms.messages import DecodeStats, GroundTruth, NeighbourState, encode
from comms.radio_relay import RadioRelay
from comms.radio_model import RadioModel


def _truth(positions: list[tuple[float, float, float]], alive: list[bool] | None = None, t_s: float = 0.0) -> GroundTruth:
    return GroundTruth(t_s=t_s, vehicle_ids=list(range(len(positions))), positions_enu_m=positions, alive=alive or [])


def _state(vid: int, seq: int, claimed: tuple[float, float] = (0.0, 0.0)) -> bytes:
    return encode(NeighbourState(sender_id=vid, role="boundary", seq=seq, t_s=0.0, position_en_m=claimed, altitude_m=10.0))


def test_gating_uses_truth_not_claimed_positions() -> None:
    relay = RadioRelay(RadioModel(25.0))
    relay.on_truth(_truth([(0, 0, 10), (20, 0, 10), (60, 0, 10)]))
    relay.on_state(2, _state(2, 1, claimed=(1.0, 0.0)), now_s=0.0)  # lies: claims to be next to 0
    relay.on_state(0, _state(0, 1, claimed=(500.0, 0.0)), now_s=0.0)  # lies: claims to be far away
    due = relay.pop_due(0.0)
    assert {r: [s for s, _ in v] for r, v in due.items()} == {1: [0]}
    assert relay.counters.out_of_range == 1 + 2


def test_spoofed_undecodable_old_and_unknown_are_dropped() -> None:
    relay = RadioRelay(RadioModel(25.0), stats=DecodeStats())
    assert relay.on_state(0, _state(0, 1), 0.0) is None and relay.counters.no_truth == 1
    relay.on_truth(_truth([(0, 0, 10), (1, 0, 10)]))
    relay.on_state(1, _state(0, 2), 0.0)  # key says 1, message says 0
    relay.on_state(0, b"\x93garbage", 0.0)
    assert relay.counters.rejected == 2
    relay.on_state(0, _state(0, 5), 0.0)
    relay.on_state(0, _state(0, 5), 0.0)
    relay.on_state(0, _state(0, 4), 0.0)
    assert relay.counters.ignored_old == 2
    relay.on_state(7, _state(7, 1), 0.0)
    assert relay.counters.no_truth == 2
    assert sum(len(v) for v in relay.pop_due(0.0).values()) == 1


def test_dead_vehicles_neither_send_nor_receive() -> None:
    relay = RadioRelay(RadioModel(25.0))
    relay.on_truth(_truth([(0, 0, 10), (1, 0, 10), (2, 0, 10)], alive=[True, False, True]))
    relay.on_state(0, _state(0, 1), 0.0)
    relay.on_state(1, _state(1, 1), 0.0)
    assert {r: [s for s, _ in v] for r, v in relay.pop_due(0.0).items()} == {2: [0]}
    assert relay.counters.no_truth == 1


def test_delays_follow_the_model_scaled_by_speed() -> None:
    model = RadioModel(25.0, loss_probability=0.0, latency_s=0.1, jitter_s=0.05, seed=3)
    relay = RadioRelay(model, speed=2.0)
    relay.on_truth(_truth([(0, 0, 10), (1, 0, 10), (2, 0, 10)]))
    relay.on_state(0, _state(0, 9), now_s=10.0)
    _, expected = model.link_fate(0, np.array([1, 2]), 9, 0.0)
    assert relay.pop_due(10.0 + 0.1 / 2 - 1e-6) == {}
    assert relay.next_due_s() == min(10.0 + expected / 2.0)
    got = relay.pop_due(10.0 + 0.15 / 2)
    assert sorted(got) == [1, 2]


def test_link_counters_match_the_model() -> None:
    model = RadioModel(100.0, loss_probability=0.4, seed=8)
    relay = RadioRelay(model)
    relay.on_truth(_truth([(0, 0, 10), (5, 0, 10), (10, 0, 10)]))
    for seq in range(300):
        relay.on_state(0, _state(0, seq), 0.0)
    stats = relay.link_stats(0.0)
    links = {(s, r): (d, lost) for s, r, d, lost in stats.links}
    for r in (1, 2):
        delivered, _ = model.link_fate(0, r, np.arange(300), 0.0)
        assert links[(0, r)] == (int(delivered.sum()), 300 - int(delivered.sum()))
    assert stats.delivered + stats.lost == 600 and abs(stats.lost / 600 - 0.4) < 0.06


def test_newer_truth_wins_older_is_ignored() -> None:
    relay = RadioRelay(RadioModel(25.0))
    relay.on_truth(_truth([(0, 0, 10), (100, 0, 10)], t_s=2.0))
    relay.on_truth(_truth([(0, 0, 10), (1, 0, 10)], t_s=1.0))
    relay.on_state(0, _state(0, 1), 0.0)
    assert relay.pop_due(0.0) == {}


def test_truth_from_a_restarted_simulator_is_adopted() -> None:
    relay = RadioRelay(RadioModel(25.0))
    relay.on_truth(_truth([(0, 0, 10), (100, 0, 10)], t_s=60.0))
    relay.on_truth(_truth([(0, 0, 10), (1, 0, 10)], t_s=0.0))  # clock went back by far more than any reordering
    relay.on_state(0, _state(0, 1), 0.0)
    assert list(relay.pop_due(0.0)) == [1]


def test_in_flight_messages_are_bounded() -> None:
    relay = RadioRelay(RadioModel(25.0, latency_s=1.0), max_in_flight=5)
    relay.on_truth(_truth([(0, 0, 10), (1, 0, 10), (2, 0, 10), (3, 0, 10)]))
    relay.on_state(0, _state(0, 1), 0.0)  # 3 receivers
    relay.on_state(1, _state(1, 1), 0.0)  # 3 more: only 2 fit
    relay.flush()
    assert relay.counters.queue_overflow == 1 and relay.counters.delivered == 6
    got = relay.pop_due(2.0)
    assert sum(len(v) for v in got.values()) == 5
    relay.on_state(2, _state(2, 1), 2.0)  # room again after delivery
    assert sum(len(v) for v in relay.pop_due(4.0).values()) == 3


def test_restarted_agent_with_seq_from_zero_is_forwarded_again() -> None:
    relay = RadioRelay(RadioModel(25.0))
    relay.on_truth(_truth([(0, 0, 10), (1, 0, 10)]))

    def state(seq: int, t_s: float) -> bytes:
        return encode(NeighbourState(sender_id=0, role="boundary", seq=seq, t_s=t_s, position_en_m=(0.0, 0.0), altitude_m=10.0))

    relay.on_state(0, state(500, 25.0), 0.0)
    relay.on_state(0, state(499, 24.95), 0.0)  # reordered: dropped
    relay.on_state(0, state(0, 30.0), 0.0)  # the agent restarted 5 s later: forwarded
    assert relay.counters.ignored_old == 1
    assert [len(v) for v in relay.pop_due(0.0).values()] == [2]


def test_only_the_header_is_read_and_a_bad_one_is_rejected_with_its_reason() -> None:
    stats = DecodeStats()
    relay = RadioRelay(RadioModel(25.0), stats=stats)
    relay.on_truth(_truth([(0, 0, 10), (1, 0, 10)]))
    header_only = msgspec.msgpack.encode({"schema": "fw/state/1", "sender_id": 0, "seq": 1, "t_s": float("nan")})
    relay.on_state(0, header_only, 0.0)  # a NaN time stamp
    relay.on_state(0, b"\x00" * 70_000, 0.0)  # above the state's size limit
    relay.on_state(0, encode(GroundTruth(t_s=0.0, vehicle_ids=[], positions_enu_m=[])), 0.0)  # another schema
    assert relay.counters.rejected == 3
    assert stats.dropped == {("NeighbourState", "invalid"): 1, ("NeighbourState", "oversized"): 1,
                             ("NeighbourState", "malformed"): 1}
    forwarded = relay.on_state(0, _state(0, 2, claimed=(3.0, 4.0)), 0.0)
    assert forwarded is not None and (forwarded.sender_id, forwarded.seq) == (0, 2)
    assert relay.pop_due(0.0)[1] == [(0, _state(0, 2, claimed=(3.0, 4.0)))]  # the sender's own bytes, untouched


def test_skipped_sequence_numbers_are_counted_as_input_gaps() -> None:
    relay = RadioRelay(RadioModel(25.0))
    relay.on_truth(_truth([(0, 0, 10), (1, 0, 10)]))
    for seq in (1, 2, 5, 6, 10):
        relay.on_state(0, _state(0, seq), 0.0)
    assert relay.counters.input_gaps == 2 + 3


def test_group_bundles_carry_what_pop_due_hands_over() -> None:
    """The emulator's group bundles give every receiver exactly the (sender, payload) list ``pop_due`` returns for
    it, in the same order, across several groups and with lost links."""
    from comms.messages import RadioGroupBundle, decode
    from comms.radio_groups import RADIO_GROUP_SIZE, selected_entries

    n = 3 * RADIO_GROUP_SIZE
    relays = [RadioRelay(RadioModel(25.0, loss_probability=0.3, latency_s=0.1, jitter_s=0.2, seed=4)) for _ in range(2)]
    for relay in relays:
        relay.on_truth(_truth([(4.0 * i, 0, 10) for i in range(n)]))
        for seq in (1, 2, 3):
            for vid in range(n):
                relay.on_state(vid, _state(vid, seq), 0.01 * seq)
    expected = relays[0].pop_due(1.0)
    bundles = relays[1].pop_due_group_bundles(1.0, 7.5)
    got: dict[int, list[tuple[int, bytes]]] = {}
    for group, payload in bundles:
        bundle = decode(RadioGroupBundle, payload)
        assert bundle is not None and bundle.t_s == 7.5
        assert len(bundle.entries) == len(set(bundle.entries))  # each message once per group
        for receiver in bundle.receivers:
            assert receiver // RADIO_GROUP_SIZE == group
            got[receiver] = [tuple(e) for e in selected_entries(bundle, receiver)]
    assert got == expected
    assert [g for g, _ in bundles] == [0, 1, 2]
    assert relays[0].counters.lost > 0 and sum(map(len, expected.values())) == relays[0].counters.delivered
