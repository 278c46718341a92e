"""The pure radio: range gating on true positions, seeded loss and delay statistics, determinism."""

from __future__ import annotations

import numpy as np
import pytest

from comms.radio_model import RadioModel, uniform_draw


def test_range_gate_is_symmetric_and_excludes_self() -> None:
    radio = RadioModel(range_m=25.0)
    pos = np.array([[0.0, 0.0], [24.9, 0.0], [25.1, 0.0], [0.0, 25.0]])
    near = radio.in_range(pos)
    assert near.tolist() == [
        [False, True, False, True],
        [True, False, True, False],
        [False, True, False, False],
        [True, False, False, False],
    ]
    assert (near == near.T).all()


def test_three_d_positions_use_slant_range() -> None:
    radio = RadioModel(range_m=10.0)
    pos = np.array([[0.0, 0.0, 0.0], [6.0, 0.0, 9.0]])  # 10.8 m slant, 6 m horizontal
    assert not radio.in_range(pos)[0, 1]
    assert radio.in_range(pos[:, :2])[0, 1]


def test_nan_position_hears_nobody() -> None:
    radio = RadioModel(range_m=100.0)
    pos = np.array([[0.0, 0.0], [np.nan, np.nan], [1.0, 1.0]])
    near = radio.in_range(pos)
    assert not near[1].any() and not near[:, 1].any()
    assert near[0, 2]


def test_broadcast_matches_receivers_of() -> None:
    rng = np.random.default_rng(3)
    pos = rng.uniform(-60, 60, size=(40, 2))
    radio = RadioModel(range_m=25.0)
    tx = radio.broadcast(pos, t_s=1.0, seq=7)
    for k in range(40):
        got = sorted(tx.receiver_index[tx.sender_index == k].tolist())
        assert got == radio.receivers_of(k, pos).tolist()
        brute = [j for j in range(40) if j != k and np.hypot(*(pos[j] - pos[k])) <= 25.0]
        assert got == brute


def test_loss_rate_and_delay_statistics_for_a_seed() -> None:
    radio = RadioModel(range_m=1e9, loss_probability=0.2, latency_s=0.05, jitter_s=0.02, seed=11)
    n, rounds = 30, 200
    pos = np.zeros((n, 2))
    delivered = 0
    total = 0
    delays: list[np.ndarray] = []
    for seq in range(rounds):
        tx = radio.broadcast(pos, t_s=seq * 0.05, seq=seq)
        total += tx.sender_index.size
        delivered += tx.heard_count
        _, _, t = tx.heard()
        delays.append(t - seq * 0.05)
    loss = 1 - delivered / total
    assert total == n * (n - 1) * rounds
    assert abs(loss - 0.2) < 0.01  # 174000 Bernoulli draws: sigma ~ 0.001
    d = np.concatenate(delays)
    assert d.min() >= 0.05 - 1e-12 and d.max() < 0.07
    assert abs(d.mean() - 0.06) < 0.001


def test_same_seed_same_fate_different_seed_different_fate() -> None:
    pos = np.random.default_rng(0).uniform(-20, 20, size=(20, 2))
    a = RadioModel(25.0, loss_probability=0.3, jitter_s=0.1, seed=5).broadcast(pos, 2.0, seq=3)
    b = RadioModel(25.0, loss_probability=0.3, jitter_s=0.1, seed=5).broadcast(pos, 2.0, seq=3)
    c = RadioModel(25.0, loss_probability=0.3, jitter_s=0.1, seed=6).broadcast(pos, 2.0, seq=3)
    assert (a.delivered == b.delivered).all()
    np.testing.assert_array_equal(a.delivery_t_s, b.delivery_t_s)
    assert (a.delivered != c.delivered).any()


def test_fate_does_not_depend_on_row_order() -> None:
    rng = np.random.default_rng(1)
    pos = rng.uniform(-20, 20, size=(15, 2))
    ids = np.arange(100, 115)
    radio = RadioModel(25.0, loss_probability=0.5, jitter_s=0.1, seed=2)
    a = radio.broadcast(pos, 0.0, seq=1, vehicle_ids=ids)
    perm = rng.permutation(15)
    b = radio.broadcast(pos[perm], 0.0, seq=1, vehicle_ids=ids[perm])
    fate_a = {(ids[s], ids[r]): (d, t) for s, r, d, t in zip(a.sender_index, a.receiver_index, a.delivered, a.delivery_t_s)}
    fate_b = {(ids[perm][s], ids[perm][r]): (d, t) for s, r, d, t in zip(b.sender_index, b.receiver_index, b.delivered, b.delivery_t_s)}
    assert fate_a.keys() == fate_b.keys()
    for k, (d, t) in fate_a.items():
        assert fate_b[k][0] == d
        assert (np.isnan(t) and np.isnan(fate_b[k][1])) or t == fate_b[k][1]


def test_send_agrees_with_broadcast_of_one_sender() -> None:
    pos = np.random.default_rng(4).uniform(-30, 30, size=(25, 2))
    radio = RadioModel(25.0, loss_probability=0.25, latency_s=0.01, jitter_s=0.03, seed=9)
    one = radio.send(3, pos, t_s=5.0, seq=42)
    all_ = radio.broadcast(pos, t_s=5.0, seq=42, senders=[3])
    np.testing.assert_array_equal(one.receiver_index, all_.receiver_index)
    np.testing.assert_array_equal(one.delivered, all_.delivered)
    np.testing.assert_array_equal(one.delivery_t_s, all_.delivery_t_s)


def test_uniform_draw_is_uniform() -> None:
    u = uniform_draw(1, np.arange(100000), 7, 3, 1)
    assert u.min() >= 0 and u.max() < 1
    hist, _ = np.histogram(u, bins=10, range=(0, 1))
    assert (np.abs(hist - 10000) < 500).all()


@pytest.mark.parametrize("kwargs", [dict(range_m=-1), dict(range_m=1, loss_probability=1.5), dict(range_m=1, latency_s=-0.1), dict(range_m=1, jitter_s=-1)])
def test_bad_parameters_are_rejected(kwargs: dict) -> None:
    with pytest.raises(ValueError):
        RadioModel(**kwargs)


def test_send_many_agrees_with_single_sends() -> None:
    pos = np.random.default_rng(6).uniform(-30, 30, size=(30, 3))
    radio = RadioModel(25.0, loss_probability=0.3, latency_s=0.01, jitter_s=0.02, seed=4)
    senders = np.array([5, 0, 29, 12])
    seqs = np.array([7, 8, 9, 10])
    times = np.array([1.0, 1.1, 1.2, 1.3])
    many = radio.send_many(senders, pos, times, seqs)
    for k, s in enumerate(senders):
        one = radio.send(int(s), pos, float(times[k]), int(seqs[k]))
        rows = many.message_index == k
        np.testing.assert_array_equal(many.receiver_index[rows], one.receiver_index)
        np.testing.assert_array_equal(many.delivered[rows], one.delivered)
        np.testing.assert_array_equal(many.delivery_t_s[rows], one.delivery_t_s)
        assert (many.sender_index[rows] == s).all()
