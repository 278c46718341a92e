"""The radio that fails like a real one: burst lengths, loss against distance, the byte budget, and both engines'
agreement on every fate (pure; no sockets)."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from comms.burst_loss import BurstLoss
from comms.byte_budget import SenderBudgets, admit
from comms.messages import GroundTruth, NeighbourState, encode
from comms.radio_relay import RadioRelay
from comms.radio_model import RadioModel, radio_model_of
from comms.signing import KEY_BYTES, MissionKey, sign
from gcs.lockstep.radio_link import InMemoryRadio
from mission_plan.scenario_schema import RadioSpec, scenario_from_table
from mission_plan.scenarios import SCENARIO_DIR
from mission_plan.table_fields import ScenarioError


def _runs(states: np.ndarray, value: bool, dt_s: float) -> np.ndarray:
    """Lengths [s] of the complete runs of ``value`` in a sampled state sequence (the first and last cut off)."""
    edges = np.flatnonzero(np.diff(states.astype(np.int8))) + 1
    bounds = np.concatenate([[0], edges, [states.size]])
    lengths = np.diff(bounds)[1:-1]
    starts = bounds[1:-2]
    return lengths[states[starts] == value] * dt_s


def test_burst_and_gap_lengths_are_exponential_with_the_configured_means() -> None:
    burst = BurstLoss(burst_mean_s=1.0, gap_mean_s=3.0)
    dt_s = 0.01
    t = np.arange(0.0, 3000.0, dt_s)
    states = burst.bad(7, 1, 2, t)
    bursts, gaps = _runs(states, True, dt_s), _runs(states, False, dt_s)
    assert bursts.size > 600
    assert bursts.mean() == pytest.approx(1.0, rel=0.08)
    assert gaps.mean() == pytest.approx(3.0, rel=0.08)
    assert states.mean() == pytest.approx(0.25, abs=0.02)
    assert np.mean(bursts > 2.0) == pytest.approx(np.exp(-2.0), abs=0.03)  # memoryless: P(L > 2 s) = e^-2


def test_burst_state_is_a_pure_function_of_the_link_and_time() -> None:
    burst = BurstLoss(0.5, 0.5)
    t = np.random.default_rng(0).uniform(0, 100, 200)
    whole = burst.bad(3, 4, 9, t)
    one_by_one = np.array([burst.bad(3, 4, 9, x) for x in t[::-1]])[::-1]
    np.testing.assert_array_equal(whole, one_by_one)
    other_direction = burst.bad(3, 9, 4, t)
    assert abs(np.corrcoef(whole, other_direction)[0, 1]) < 0.15  # each directed link has its own chain


def test_loss_rises_with_distance_toward_the_range_limit() -> None:
    radio = RadioModel(range_m=100.0, edge_loss_probability=0.6, edge_loss_exponent=2.0, seed=5)
    seq = np.arange(20000)
    measured = []
    for d in (0.0, 50.0, 100.0):
        delivered, _ = radio.link_fate(1, 2, seq, 0.0, distance_m=np.full(seq.shape, d))
        measured.append(1.0 - delivered.mean())
    assert measured == pytest.approx([0.0, 0.15, 0.6], abs=0.015)
    positions = np.array([[0.0, 0.0], [30.0, 0.0], [95.0, 0.0]])
    lost = np.zeros(3)
    for k in range(1200):
        tx = radio.broadcast(positions, 0.05 * k, seq=k, senders=[0])
        lost[tx.receiver_index[~tx.delivered]] += 1
    assert lost[2] / 1200 == pytest.approx(0.6 * 0.95 ** 2, abs=0.04)
    assert lost[1] / 1200 == pytest.approx(0.6 * 0.3 ** 2, abs=0.025)


def test_average_loss_over_bursts_matches_the_stationary_law() -> None:
    radio = RadioModel(range_m=1e9, seed=2, burst=BurstLoss(1.0, 1.0), burst_loss_probability=1.0)
    assert radio.mean_loss_probability == pytest.approx(0.5)
    t = np.arange(0, 2000, 0.05)
    delivered, _ = radio.link_fate(1, 2, np.arange(t.size), t)
    assert 1.0 - delivered.mean() == pytest.approx(0.5, abs=0.05)
    losses = ~delivered
    after_loss = losses[1:][losses[:-1]].mean()  # bursty: a loss is followed by a loss far more often than 50 %
    assert after_loss > 0.9


def test_byte_budget_lets_through_the_rate_after_the_first_second() -> None:
    level = None
    sent = 0
    for k in range(200):  # 10 s of 200-byte messages at 20 Hz: 4000 B/s offered, 1000 B/s allowed, 1 s deep
        ok, level = admit(level, 200, 0.05 * k, rate_bytes_per_s=1000.0, depth_bytes=1000.0)
        sent += ok
    assert sent * 200 == pytest.approx(1000.0 + 1000.0 * 9.95, abs=200.0)
    budgets = SenderBudgets(0.0)
    assert all(budgets.admit(1, 10_000, 0.0) for _ in range(100)) and budgets.dropped == 0


def _msg(vid: int, seq: int, t_s: float) -> NeighbourState:
    return NeighbourState(sender_id=vid, role="boundary", seq=seq, t_s=t_s, position_en_m=(0.0, 0.0), altitude_m=10.0)


def test_both_engines_give_the_same_fate_with_bursts_distance_and_a_byte_budget() -> None:
    model = RadioModel(range_m=30.0, loss_probability=0.1, seed=9, burst=BurstLoss(0.5, 1.0),
                       burst_loss_probability=0.9, edge_loss_probability=0.5, bandwidth_bytes_per_s=1000.0)
    ids = [3, 5, 8]
    positions = np.array([[0.0, 0.0, 10.0], [12.0, 0.0, 10.0], [0.0, 27.0, 10.0]])
    lockstep = InMemoryRadio(model, ids)
    relay = RadioRelay(model)
    key = MissionKey(bytes(KEY_BYTES))
    lock_fates: set[tuple[int, int, int]] = set()
    relay_fates: set[tuple[int, int, int]] = set()
    for k in range(200):
        t_s = 0.05 * k
        messages = [_msg(v, k + 1, t_s) for v in ids]
        lockstep.broadcast(t_s, positions, messages)
        for receiver, inbox in zip(ids, lockstep.deliver(t_s)):
            lock_fates |= {(m.sender_id, receiver, m.seq) for m in inbox.states}
        relay.on_truth(GroundTruth(t_s=t_s, vehicle_ids=ids, positions_enu_m=[tuple(p) for p in positions]))
        for v, m in zip(ids, messages):  # signed as every mission process sends them: the budget counts the tag
            relay.on_state(v, sign(key, encode(m), v, round(t_s * 1e6)), t_s)
        for receiver, entries in relay.pop_due(t_s).items():
            relay_fates |= {(sender, receiver, k + 1) for sender, _ in entries}
    assert lock_fates == relay_fates
    assert relay.counters.over_budget == lockstep.budgets.dropped > 0
    assert 0 < len(lock_fates) < 200 * 6


def test_radio_keys_are_validated_naming_the_field() -> None:
    table = tomllib.loads((SCENARIO_DIR / "circle.toml").read_text())
    with pytest.raises(ScenarioError, match=r"radio\.burst_gap_s"):
        scenario_from_table({**table, "radio": {"burst_mean_s": 1.0}})
    with pytest.raises(ScenarioError, match=r"radio\.burst_loss"):
        scenario_from_table({**table, "radio": {"burst_loss": 1.5}})
    with pytest.raises(ScenarioError, match=r"radio\.gcs_lossless"):
        scenario_from_table({**table, "radio": {"gcs_lossless": "yes"}})
    with pytest.raises(ScenarioError, match=r"radio\.bandwidth_bytes_per_s"):
        scenario_from_table({**table, "radio": {"bandwidth_bytes_per_s": -1}})
    model = radio_model_of(RadioSpec(burst_mean_s=1.0, burst_gap_s=3.0, burst_loss=0.8), seed=4)
    assert model.burst == BurstLoss(1.0, 3.0) and model.burst_loss_probability == 0.8 and model.seed == 4
