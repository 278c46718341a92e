import math

import numpy as np
import pytest

from gcs.metrics import (
    centring_errors_m,
    climb_events_from_altitude,
    pairwise_safety,
    path_lengths_m,
    recovery_time_s,
    speeds_mps,
    vehicle_losses,
)


def test_min_distance_and_near_misses_of_three_vehicles() -> None:
    # Vehicle 1 flies through vehicle 0's position and back; vehicle 2 stays far away.
    x1 = [3.0, 0.5, 3.0, 0.8, 3.0]
    pos = np.array([[[0.0, 0.0, 10.0], [x, 0.0, 10.0], [50.0, 0.0, 10.0]] for x in x1])
    stats = pairwise_safety(pos, np.ones((5, 3), bool))
    assert stats.min_distance_m == pytest.approx(0.5)
    assert stats.closest_pair == (0, 1)
    assert stats.near_miss_pairs == [(0, 1)]
    assert stats.near_miss_events == 2
    assert np.allclose(stats.min_distance_series_m, x1)


def test_dead_vehicles_do_not_count_and_small_chunks_agree() -> None:
    rng = np.random.default_rng(0)
    pos = rng.uniform(0.0, 20.0, (30, 12, 3))
    alive = rng.random((30, 12)) > 0.2
    big = pairwise_safety(pos, alive)
    small = pairwise_safety(pos, alive, chunk_elements=1)
    assert big.min_distance_m == small.min_distance_m
    assert big.near_miss_events == small.near_miss_events
    assert big.near_miss_pairs == small.near_miss_pairs
    dead = pairwise_safety(np.zeros((3, 2, 3)), np.array([[True, False]] * 3))
    assert math.isnan(dead.min_distance_m) and dead.near_miss_events == 0


def test_losses_and_recovery_time() -> None:
    t = np.arange(0.0, 10.0, 0.5)
    alive = np.ones((len(t), 3), bool)
    alive[8:, 2] = False  # lost at t = 4.0
    losses = vehicle_losses(t, alive)
    assert [(loss.index, loss.t_s) for loss in losses] == [(2, 4.0)]
    cv = np.full(len(t), 0.02)
    cv[8:] = 0.4
    cv[12] = 0.05  # a lucky dip at 6.0 s that does not hold
    cv[15:] = 0.05  # recovered from 7.5 s on
    assert recovery_time_s(t, cv, 4.0, hold_s=1.0) == pytest.approx(3.5)
    assert recovery_time_s(t, cv, 4.0, hold_s=0.0) == pytest.approx(2.0)
    assert math.isnan(recovery_time_s(t, np.full(len(t), 0.5), 4.0))


def test_path_length_speed_and_climbs() -> None:
    t = np.array([0.0, 1.0, 2.0, 3.0])
    pos = np.zeros((4, 2, 3))
    pos[:, 0, 0] = [0.0, 3.0, 6.0, 6.0]
    pos[:, 0, 2] = [10.0, 10.0, 14.0, 10.0]
    alive = np.ones((4, 2), bool)
    assert np.allclose(path_lengths_m(pos, alive), [3.0 + 5.0 + 4.0, 0.0])
    assert np.allclose(speeds_mps(t, pos, alive)[:, 0], [3.0, 3.0, 0.0])
    alive[3, 0] = False
    assert path_lengths_m(pos, alive)[0] == pytest.approx(8.0)
    altitude = np.array([10, 10, 13, 10, 10, 12.5, 10, 10], float)[:, None]
    assert climb_events_from_altitude(altitude, np.ones_like(altitude, bool)).tolist() == [2]


def test_centring_error_is_horizontal_distance_to_the_centroid() -> None:
    assert np.allclose(centring_errors_m([[3.0, 4.0, 10.0], [0.0, 0.0, 5.0]], [0.0, 0.0]), [5.0, 0.0])
