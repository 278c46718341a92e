"""A boundary drone reports the edge points continuous with the edge it tracks, not a second boundary beside it."""

from __future__ import annotations

import numpy as np

from vehicle_agents.perception.edge_continuity import continuous_edge_points

FOOTPRINT_M = 11.5
TANGENT = np.array([0.0, 1.0])
NORMAL = np.array([1.0, 0.0])


def arc(radius_m: float, across_at_centre_m: float, along_m: np.ndarray) -> np.ndarray:
    """Points of a circle of ``radius_m`` (centre on the water side, west) through (``across_at_centre_m``, 0)."""
    across = across_at_centre_m - (radius_m - np.sqrt(radius_m ** 2 - along_m ** 2))
    return np.column_stack([across, along_m])


def test_a_curved_shore_alone_is_kept_whole() -> None:
    shore = arc(12.0, 0.3, np.linspace(-5.5, 5.5, 40))
    kept = continuous_edge_points(shore, TANGENT, NORMAL, FOOTPRINT_M)
    assert kept.shape == shore.shape
    assert np.array_equal(kept, shore[np.argsort(shore @ TANGENT)])


def test_a_shadow_edge_metres_inside_the_water_is_left_out() -> None:
    shore = arc(12.0, 0.3, np.linspace(-5.5, 5.5, 40))
    shadow = np.column_stack([np.full(20, -4.0), np.linspace(-1.0, 5.5, 20)])
    kept = continuous_edge_points(np.concatenate([shadow, shore]), TANGENT, NORMAL, FOOTPRINT_M)
    assert kept.shape == shore.shape
    assert np.all(kept @ NORMAL > -1.5)


def test_the_walk_starts_at_the_edge_below_the_drone_even_when_a_false_edge_has_more_points() -> None:
    shore = np.column_stack([np.full(15, 0.5), np.linspace(-1.5, 1.5, 15)])
    false_edge = np.column_stack([np.full(40, -3.5), np.linspace(1.0, 5.5, 40)])
    kept = continuous_edge_points(np.concatenate([false_edge, shore]), TANGENT, NORMAL, FOOTPRINT_M)
    assert len(kept) == 15 and np.allclose(kept @ NORMAL, 0.5)


def test_a_bend_of_45_degrees_is_followed() -> None:
    along = np.linspace(0.0, 4.0, 21)
    corner = np.concatenate([np.column_stack([np.zeros(21), -along[::-1]]), np.column_stack([along, along])[1:]])
    kept = continuous_edge_points(corner, TANGENT, NORMAL, FOOTPRINT_M)
    assert len(kept) == len(corner)


def test_too_few_points_are_reported_as_they_are() -> None:
    two = np.array([[0.0, 0.0], [5.0, 1.0]])
    assert np.array_equal(continuous_edge_points(two, TANGENT, NORMAL, FOOTPRINT_M), two)
    assert continuous_edge_points(np.zeros((0, 2)), TANGENT, NORMAL, FOOTPRINT_M).shape == (0, 2)
