"""Batches held as delivery matrices hand out exactly what the row form hands out: the same deliveries in the same
order, the same group bundle bytes, the same counters and link totals."""

from __future__ import annotations

import numpy as np
import pytest

from comms import radio_relay
from comms.burst_loss import BurstLoss
from comms.link_counters import LinkCounters
from comms.messages import GroundTruth, NeighbourState, encode
from comms.radio_model import RadioModel
from comms.radio_relay import RadioRelay


def _state(vid: int, seq: int, t_s: float) -> bytes:
    return encode(NeighbourState(sender_id=vid, role="boundary", seq=seq, t_s=t_s, position_en_m=(0.0, 0.0),
                                 altitude_m=10.0))


def _fleet(seed: int, count: int) -> tuple[list[int], np.ndarray]:
    """Vehicle ids out of order with gaps (several groups), positions in a 60 m square, one dead."""
    rng = np.random.default_rng(seed)
    ids = rng.permutation(np.arange(1, 3 * count))[:count].tolist()
    positions = np.column_stack([rng.uniform(0, 60, count), rng.uniform(0, 60, count), rng.uniform(5, 15, count)])
    positions[count // 2] = np.nan
    return ids, positions


def _run(relay: RadioRelay, seed: int, count: int, cycles: int, tick_s: float) -> list[object]:
    """Feed a few cycles of states (a truth every other cycle, vehicles moving), record every hand-out."""
    ids, positions = _fleet(seed, count)
    rng = np.random.default_rng(seed + 100)
    out: list[object] = []
    seq = 0
    for cycle in range(cycles):
        now_s = cycle * tick_s
        if cycle % 2 == 0:
            moved = positions + 0.5 * cycle
            relay.on_truth(GroundTruth(t_s=now_s, vehicle_ids=ids, positions_enu_m=[tuple(p) for p in moved.tolist()],
                                       alive=[bool(np.isfinite(p).all()) for p in moved]))
        seq += 1
        for vid in rng.permutation(ids)[: count // 2].tolist():
            relay.on_state(vid, _state(vid, seq, now_s), now_s)
        if cycle % 3 == 2:
            out.append(relay.pop_due(now_s))
        else:
            out.append(relay.pop_due_group_bundles(now_s, now_s))
    out.append(relay.pop_due_group_bundles(1e9, 1e9))
    out.append(relay.link_stats(1e9))
    out.append(relay.counters)
    return out


RADIOS = {
    "lossless": RadioModel(25.0),
    "latency": RadioModel(25.0, latency_s=0.012),
    "losses": RadioModel(25.0, loss_probability=0.2, latency_s=0.004, seed=3, burst=BurstLoss(0.5, 1.0),
                         burst_loss_probability=0.8, edge_loss_probability=0.3),
}


@pytest.mark.parametrize("name", sorted(RADIOS))
@pytest.mark.parametrize("ground", [None, (30.0, 30.0, 2.0)])
def test_matrix_form_hands_out_what_the_row_form_does(name: str, ground: tuple[float, float, float] | None,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    matrix = _run(RadioRelay(RADIOS[name], ground_node_enu_m=ground), seed=7, count=40, cycles=12, tick_s=0.005)
    monkeypatch.setattr(radio_relay, "MAX_MATRIX_ID", -1)  # no id fits a matrix: every batch in rows
    rows = _run(RadioRelay(RADIOS[name], ground_node_enu_m=ground), seed=7, count=40, cycles=12, tick_s=0.005)
    assert matrix == rows
    assert matrix[-1].delivered > 0
    assert name != "losses" or matrix[-1].lost > 0


def test_a_batch_in_rows_takes_the_matrices_in_flight_along() -> None:
    """Jitter (a delay per link) is held in rows; matrices still in flight join them, in order."""
    relays = [RadioRelay(RadioModel(25.0, latency_s=0.01)) for _ in range(2)]
    truth = GroundTruth(t_s=0.0, vehicle_ids=[1, 2, 3], positions_enu_m=[(0, 0, 10), (5, 0, 10), (10, 0, 10)])
    for relay in relays:
        relay.on_truth(truth)
        relay.on_state(1, _state(1, 1, 0.0), 0.0)
        relay.flush()
    relays[0].on_state(2, _state(2, 1, 0.0), 0.002)
    relays[0].on_state(3, _state(3, 1, 0.0), 0.001)  # a batch with two arrival times: held in rows
    relays[1].on_state(2, _state(2, 1, 0.0), 0.002)
    relays[1].flush()
    relays[1].on_state(3, _state(3, 1, 0.0), 0.001)
    got = [relay.pop_due(1.0) for relay in relays]
    assert got[0] == got[1]
    assert [s for s, _ in got[0][2]] == [1, 3]  # by due time: 1 (0.010), 3 (0.011)


def test_in_flight_bound_keeps_the_same_deliveries(monkeypatch: pytest.MonkeyPatch) -> None:
    def run() -> tuple[dict[int, list[tuple[int, bytes]]], int]:
        relay = RadioRelay(RadioModel(25.0, latency_s=0.1), max_in_flight=7)
        relay.on_truth(GroundTruth(t_s=0.0, vehicle_ids=[4, 2, 9, 5], positions_enu_m=[(0, 0, 10)] * 4))
        for vid in (9, 2, 5):
            relay.on_state(vid, _state(vid, 1, 0.0), 0.0)
        return relay.pop_due(1.0), relay.counters.queue_overflow

    matrix = run()
    monkeypatch.setattr(radio_relay, "MAX_MATRIX_ID", -1)
    assert matrix == run()
    assert matrix[1] == 9 - 7


def test_heard_by_is_send_manys_gate_receiver_major() -> None:
    rng = np.random.default_rng(2)
    positions = rng.uniform(-40, 40, (50, 3))
    positions[7] = np.nan
    senders = np.array([3, 0, 49, 3, 20])
    model = RadioModel(30.0)
    tx = model.send_many(senders, positions, 0.0, 1)
    expected = np.zeros((50, senders.size), dtype=bool)
    expected[tx.receiver_index, tx.message_index] = True
    assert np.array_equal(model.heard_by(positions, senders), expected)


def test_link_counters_fold_noted_matrices_and_lost_links() -> None:
    counters = LinkCounters()
    counters.slots_of([5, 1, 2])
    delivered = np.zeros((16, 3), dtype=bool)
    delivered[[1, 2], 0] = True  # message 0 from 5 reaches 1 and 2
    delivered[2, 1] = True  # message 1 from 1 reaches 2
    delivered[2, 2] = True  # message 2 from 5 reaches 2 again
    counters.note_matrix(np.array([5, 1, 5]), delivered, np.array([1]), np.array([5]))
    counters.add_rows(np.array([2]), np.array([1]), np.array([False]))
    assert sorted(counters.links()) == [[1, 2, 1, 0], [1, 5, 0, 1], [2, 1, 0, 1], [5, 1, 1, 0], [5, 2, 2, 0]]
