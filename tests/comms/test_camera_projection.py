"""The body-fixed camera's pixel-to-ground homography: level it is SPEC §3's nadir map; a known tilt moves the
footprint by h·tan(θ) the way the camera points."""

from __future__ import annotations

import math

import numpy as np
import pytest

from comms.camera_projection import pixel_to_ground, project_pixels
from comms.frames import body_to_ned_matrix

W, H, FOV = 128, 128, 60.0


def centre_of_view(height_m: float, roll: float, pitch: float, yaw: float) -> np.ndarray:
    g = pixel_to_ground(W, H, FOV, height_m, roll, pitch, yaw)
    assert g is not None
    return project_pixels(g, np.array(W / 2.0), np.array(H / 2.0))


def test_level_camera_is_the_nadir_map() -> None:
    g = pixel_to_ground(W, H, FOV, 10.0, 0.0, 0.0, 0.0)
    gsd = 2 * 10.0 * math.tan(math.radians(FOV / 2)) / W
    corners = project_pixels(g, np.array([0.0, W, 0.0]), np.array([0.0, 0.0, H]))
    np.testing.assert_allclose(corners, [[-W / 2 * gsd, H / 2 * gsd], [W / 2 * gsd, H / 2 * gsd],
                                         [-W / 2 * gsd, -H / 2 * gsd]], atol=1e-9)


@pytest.mark.parametrize("theta_deg", [3.0, 10.0, 20.0])
@pytest.mark.parametrize("yaw_deg", [0.0, 90.0, 217.0])
@pytest.mark.parametrize("height_m", [5.0, 10.0, 25.0])
def test_a_known_tilt_moves_the_footprint_by_h_tan_theta(theta_deg: float, yaw_deg: float, height_m: float) -> None:
    theta, yaw = math.radians(theta_deg), math.radians(yaw_deg)
    shift = height_m * math.tan(theta)
    forward = np.array([math.sin(yaw), math.cos(yaw)])  # east, north of the nose
    right = np.array([math.cos(yaw), -math.sin(yaw)])
    # Nose up: the belly, and the camera, turn forward. Right side down: the camera turns left.
    np.testing.assert_allclose(centre_of_view(height_m, 0.0, theta, yaw), shift * forward, atol=1e-9)
    np.testing.assert_allclose(centre_of_view(height_m, theta, 0.0, yaw), -shift * right, atol=1e-9)


def test_the_horizon_gives_no_projection() -> None:
    assert pixel_to_ground(W, H, FOV, 10.0, 0.0, math.radians(75.0), 0.0) is None


def test_body_rotation_is_orthonormal_and_yaw_turns_forward_clockwise_from_north() -> None:
    r = body_to_ned_matrix(0.3, -0.2, 1.1)
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(body_to_ned_matrix(0.0, 0.0, math.pi / 2) @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
                               atol=1e-12)


def test_points_project_as_the_full_homography_gives_them_level_and_tilted() -> None:
    rng = np.random.default_rng(4)
    points = rng.uniform(0.0, 128.0, (300, 2))
    x, y = points[:, 0], points[:, 1]
    for roll, pitch, yaw in ((0.0, 0.0, 0.0), (0.0, 0.0, 2.1), (0.0, 0.0, -0.7), (0.1, -0.2, 0.4)):
        g = pixel_to_ground(128, 128, 60.0, 10.0, roll, pitch, yaw)
        assert g is not None
        w = g[2, 0] * x + g[2, 1] * y + g[2, 2]
        east, north = g[0, 0] * x + g[0, 1] * y + g[0, 2], g[1, 0] * x + g[1, 1] * y + g[1, 2]
        expected = np.stack((east / w, north / w), -1)
        assert project_pixels(g, x, y).tobytes() == expected.tobytes()
