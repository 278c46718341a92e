"""The edge's projection to the ground and its normal (pure functions of image points and the homography)."""

from __future__ import annotations

import math

import numpy as np

from comms.camera_projection import pixel_to_ground, project_pixels
from vehicle_agents.perception.segmentation import _edge_normal, _project


def test_points_project_as_the_shared_camera_law_gives_them_level_and_tilted() -> None:
    rng = np.random.default_rng(4)
    points = rng.uniform(0.0, 128.0, (300, 2))
    for roll, pitch, yaw in ((0.0, 0.0, 0.0), (0.0, 0.0, 2.1), (0.0, 0.0, -0.7), (0.1, -0.2, 0.4)):
        to_ground = pixel_to_ground(128, 128, 60.0, 10.0, roll, pitch, yaw)
        assert to_ground is not None
        expected = project_pixels(to_ground, points[:, 0], points[:, 1])
        assert _project(to_ground, points).tobytes() == expected.tobytes()


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
