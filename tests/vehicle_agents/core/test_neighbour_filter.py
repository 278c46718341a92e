"""The neighbour filter: prediction error on a known trajectory, covariance growth in a gap, the drop at the bound,
and its use by the onboard core (pure)."""

from __future__ import annotations

import numpy as np
import pytest

from comms.messages import NeighbourState
from vehicle_agents.core.neighbour_filter import EMPTY_BANK, FilterNoise, at_time, position_std_m, predict, update


def _state(vid: int, t_s: float, p: np.ndarray, v: np.ndarray, seq: int = 1) -> NeighbourState:
    return NeighbourState(sender_id=vid, role="boundary", seq=seq, t_s=t_s, position_en_m=(float(p[0]), float(p[1])),
                          velocity_en_mps=(float(v[0]), float(v[1])), altitude_m=10.0)


def _circle(t_s: float) -> tuple[np.ndarray, np.ndarray]:
    """A drone on a 12 m circle at 3 m/s (the improved mode's encircling)."""
    w = 3.0 / 12.0
    return (12.0 * np.array([np.cos(w * t_s), np.sin(w * t_s)]),
            3.0 * np.array([-np.sin(w * t_s), np.cos(w * t_s)]))


def test_prediction_to_the_control_time_beats_the_last_message_on_a_known_trajectory() -> None:
    noise = FilterNoise()
    rng = np.random.default_rng(1)
    bank = EMPTY_BANK
    filtered, stale = [], []
    for k in range(400):
        t_msg = 0.05 * k
        if rng.uniform() < 0.5:  # half the messages lost
            continue
        p, v = _circle(t_msg)
        p_meas = p + rng.normal(0.0, 0.1, 2)
        bank = update(bank, [_state(7, t_msg, p_meas, v + rng.normal(0.0, 0.1, 2), seq=k + 1)], noise)
        t_control = t_msg + 0.2  # 200 ms latency: the laws act 0.2 s after the state was true
        _, x, _ = at_time(bank, t_control, noise)
        truth, _ = _circle(t_control)
        filtered.append(np.linalg.norm(x[0, :2] - truth))
        stale.append(np.linalg.norm(p_meas - truth))
    assert np.mean(filtered[20:]) < 0.5 * np.mean(stale[20:])  # the last message is 0.6 m behind; the filter is not
    assert np.max(filtered[20:]) < 0.4


def test_covariance_grows_in_a_gap_as_the_process_noise_says() -> None:
    noise = FilterNoise(accel_psd_m2ps3=1.0, position_std_m=0.3, velocity_std_mps=0.3, position_bound_m=100.0)
    bank = update(EMPTY_BANK, [_state(2, 0.0, np.zeros(2), np.zeros(2))], noise)
    stds = [position_std_m(at_time(bank, t, noise)[2])[0] for t in (0.0, 1.0, 2.0, 3.0)]
    assert np.all(np.diff(stds) > 0.0)
    expected = [np.sqrt(0.09 + 0.09 * t ** 2 + t ** 3 / 3.0) for t in (0.0, 1.0, 2.0, 3.0)]
    np.testing.assert_allclose(stds, expected, rtol=1e-9)


def test_a_silent_neighbour_is_dropped_when_its_uncertainty_passes_the_bound_not_before() -> None:
    noise = FilterNoise(accel_psd_m2ps3=1.0, position_bound_m=3.0)
    bank = update(EMPTY_BANK, [_state(4, 10.0, np.zeros(2), np.ones(2))], noise)
    grid_s = np.arange(0.0, 10.0, 0.05)
    variance = 0.09 + 0.09 * grid_s ** 2 + grid_s ** 3 / 3.0  # P_pp after a gap: R_p + R_v t² + q t³ / 3
    gap_s = float(grid_s[np.argmax(variance > 9.0)])
    kept, x, _ = at_time(bank, 10.0 + gap_s - 0.05, noise)
    assert kept.ids.tolist() == [4]
    np.testing.assert_allclose(x[0, :2], (gap_s - 0.05) * np.ones(2))
    dropped, x, _ = at_time(bank, 10.0 + gap_s, noise)
    assert len(dropped) == 0 and x.shape == (0, 4)
    assert 2.5 < gap_s < 3.5


def test_old_or_relayed_copies_do_not_move_a_track_back_and_many_neighbours_update_at_once() -> None:
    noise = FilterNoise()
    states = [_state(vid, 1.0, np.array([vid, 0.0]), np.zeros(2)) for vid in range(200, 0, -1)]
    bank = update(EMPTY_BANK, states, noise)
    assert bank.ids.tolist() == list(range(1, 201))
    newer = update(bank, [_state(5, 2.0, np.array([9.0, 9.0]), np.zeros(2), seq=2),
                          _state(6, 0.5, np.array([-50.0, 0.0]), np.zeros(2), seq=0)], noise)
    assert newer.t_s[newer.ids == 5][0] == 2.0 and newer.x[newer.ids == 5][0, 0] > 7.0
    np.testing.assert_array_equal(newer.x[newer.ids == 6], bank.x[bank.ids == 6])


@pytest.mark.parametrize("gap_s", [0.5, 2.0])
def test_update_shrinks_the_uncertainty_again(gap_s: float) -> None:
    noise = FilterNoise()
    bank = update(EMPTY_BANK, [_state(1, 0.0, np.zeros(2), np.zeros(2))], noise)
    before = position_std_m(at_time(bank, gap_s, noise)[2])[0]
    bank = update(bank, [_state(1, gap_s, np.zeros(2), np.zeros(2), seq=2)], noise)
    after = position_std_m(at_time(bank, gap_s, noise)[2])[0]
    assert after < before and after <= noise.position_std_m + 1e-9


def _update_by_sorting(bank, states, noise):  # noqa: ANN001, ANN202 - the reference: tracks matched by array sorts
    ids = np.array([m.sender_id for m in states], dtype=np.int64)
    t_s = np.array([m.t_s for m in states])
    z = np.array([(*m.position_en_m, *m.velocity_en_mps) for m in states]).reshape(-1, 4)
    order = np.lexsort((-t_s, ids))
    ids, t_s, z = ids[order], t_s[order], z[order]
    first = np.ones(ids.size, dtype=bool)
    first[1:] = ids[1:] != ids[:-1]
    ids, t_s, z = ids[first], t_s[first], z[first]
    r = noise.measurement_variance
    slot = np.searchsorted(bank.ids, ids)
    clipped = np.minimum(slot, max(len(bank) - 1, 0))
    known = (slot < len(bank)) & (bank.ids[clipped] == ids) if len(bank) else np.zeros(ids.size, dtype=bool)
    x, p, track_t = bank.x.copy(), bank.p.copy(), bank.t_s.copy()
    fresh = known & (t_s > track_t[clipped]) if len(bank) else known
    if np.any(fresh):
        k = slot[fresh]
        xp, pp = predict(x[k], p[k], t_s[fresh] - track_t[k], noise.accel_psd_m2ps3)
        gain = np.linalg.solve(pp + np.diag(r)[None], pp).transpose(0, 2, 1)
        x[k] = xp + np.einsum("mij,mj->mi", gain, z[fresh] - xp)
        p_upd = pp - gain @ pp
        p[k] = 0.5 * (p_upd + p_upd.transpose(0, 2, 1))
        track_t[k] = t_s[fresh]
    new = ~known
    all_ids = np.concatenate([bank.ids, ids[new]])
    keep = np.argsort(all_ids, kind="stable")
    all_p = np.concatenate([p, np.broadcast_to(np.diag(r), (int(new.sum()), 4, 4))])
    return all_ids[keep], np.concatenate([track_t, t_s[new]])[keep], np.concatenate([x, z[new]])[keep], all_p[keep]


def test_measurements_meet_their_tracks_as_when_matched_by_sorting_bit_for_bit() -> None:
    """Each sender's newest measurement (the first of equal time stamps) updates its track, older ones are
    ignored, new senders start tracks in id order: the same floats, bit for bit, as matching by array sorts."""
    noise = FilterNoise()
    rng = np.random.default_rng(3)
    bank = EMPTY_BANK
    for step in range(300):
        t_now = 0.05 * step
        states = [_state(int(rng.integers(1, 12)), t_now - float(rng.choice([0.0, 0.05, 0.1, 0.5])),
                         rng.normal(0.0, 20.0, 2), rng.normal(0.0, 2.0, 2)) for _ in range(int(rng.integers(1, 15)))]
        expected = _update_by_sorting(bank, states, noise)
        bank = update(bank, states, noise)
        for got, want in zip((bank.ids, bank.t_s, bank.x, bank.p), expected):
            assert got.shape == want.shape and got.tobytes() == want.tobytes()
