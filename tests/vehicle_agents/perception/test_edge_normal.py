"""The edge's normal: across its points, towards the land (a pure function of the edge points)."""

from __future__ import annotations

import math

import numpy as np

from vehicle_agents.perception.segmentation import _edge_normal


def test_the_normal_lies_across_the_points_and_towards_the_land() -> None:
    along = np.linspace(-3.0, 3.0, 40)
    tangent = np.array([math.cos(0.3), math.sin(0.3)])
    points = along[:, None] * tangent + np.array([1.0, -2.0])
    normal = _edge_normal(points, 5.0, -1.0)
    assert normal is not None
    assert math.isclose(float(np.hypot(*normal)), 1.0)
    assert abs(float(normal @ tangent)) < 1e-12
    assert float(normal @ np.array([5.0, -1.0])) > 0.0
    flipped = _edge_normal(points, -5.0, 1.0)
    assert flipped is not None and np.allclose(flipped, -normal)


def test_without_points_the_normal_is_the_centroid_line_and_none_when_that_is_null() -> None:
    normal = _edge_normal(np.zeros((0, 2)), 3.0, 4.0)
    assert normal is not None and np.allclose(normal, [0.6, 0.8])
    assert _edge_normal(np.zeros((1, 2)), 0.0, 0.0) is None
