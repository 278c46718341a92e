"""The geometric alerts: ring gaps against the ideal share of the perimeter, and edge stretches no camera sees."""

from __future__ import annotations

import math

import numpy as np

from gcs.dashboard.alerts import ring_gaps, uncovered_edge_m


def _ring(n: int, radius_m: float) -> np.ndarray:
    a = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    return np.stack([radius_m * np.cos(a), radius_m * np.sin(a)], axis=1)


def test_an_even_ring_has_no_gap_and_a_missing_drone_makes_one_between_its_neighbours() -> None:
    ids = [10, 11, 12, 13, 14, 15, 16, 17]
    positions = _ring(8, 20.0)
    perimeter = 2 * math.pi * 20.0
    assert ring_gaps(ids, positions, perimeter) == []
    positions[3] = np.nan  # vehicle 13 lost
    gaps = ring_gaps(ids, positions, perimeter)
    assert [(g.vehicle_a, g.vehicle_b) for g in gaps] == [(12, 14)]
    assert gaps[0].ideal_m == perimeter / 7
    assert gaps[0].gap_m > 1.5 * gaps[0].ideal_m


def test_fewer_than_three_drones_make_no_ring() -> None:
    assert ring_gaps([1, 2], np.array([[0.0, 0.0], [100.0, 0.0]]), 50.0) == []


def test_an_edge_under_every_footprint_is_seen_and_a_hole_is_measured() -> None:
    square = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])
    corners = square.copy()
    assert uncovered_edge_m(square, corners, np.full(4, 12.0)) == []
    # footprints of side 4 on the four corners leave 6 m of each 10 m side unseen
    unseen = uncovered_edge_m(square, corners, np.full(4, 4.0))
    assert len(unseen) == 4 and np.allclose(unseen, 6.0)
    # no footprint at all: the whole perimeter, as one stretch
    assert np.allclose(uncovered_edge_m(square, np.zeros((0, 2)), np.zeros(0)), [40.0])
