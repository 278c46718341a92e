"""The camera hangs on a tilting drone: a tilted body's frame is the ground h·tan(θ) away, perception projects
with the reported attitude, and an accelerating multicopter leans into its acceleration."""

from __future__ import annotations

import math

import numpy as np

from mock_autopilot.camera.body_tilt import tilt_from_acceleration_rad
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.camera.render import CameraPose, ground_points_en_m, render_frame
from mock_autopilot.camera.truth import ACCURACY_FLOODS, truth_reference
from mock_autopilot.world.config import flood_model_from_config
from vehicle_agents.perception.segmentation import perceive


def test_tilted_footprint_centre_moves_by_h_tan_theta() -> None:
    camera = CameraModel()
    for theta in (0.05, 0.2):
        points = ground_points_en_m(camera, (3.0, -2.0, 10.0), 0.0, tilt_rad=(0.0, theta))
        centre = points[63:65, 63:65].reshape(-1, 2).mean(axis=0)
        np.testing.assert_allclose(centre, [3.0, -2.0 + 10.0 * math.tan(theta)], atol=1e-3)


def test_a_tilted_frame_sees_the_shore_where_a_level_camera_h_tan_theta_away_sees_it() -> None:
    flood = flood_model_from_config(ACCURACY_FLOODS["circle"])
    theta = math.radians(8.0)
    tilted = render_frame(flood, 0.0, (12.0, 0.0, 10.0), math.pi / 2, CameraModel(), 2,
                          pose=CameraPose(tilt_rad=(0.0, theta)))
    # Facing east with the nose up, the camera looks 10 tan(8°) = 1.4 m further east.
    moved = render_frame(flood, 0.0, (12.0 + 10.0 * math.tan(theta), 0.0, 10.0), math.pi / 2, CameraModel(), 2)
    centre = slice(48, 80)
    agree = (tilted.water_mask[centre, centre] == moved.water_mask[centre, centre]).mean()
    assert agree > 0.97
    level = render_frame(flood, 0.0, (12.0, 0.0, 10.0), math.pi / 2, CameraModel(), 2)
    assert (level.water_mask[centre, centre] == moved.water_mask[centre, centre]).mean() < 0.9


def test_perception_projects_with_the_reported_attitude() -> None:
    flood = flood_model_from_config(ACCURACY_FLOODS["nonconvex"])
    camera = CameraModel()
    position, yaw, tilt = (14.0, 3.0, 10.0), 0.4, (math.radians(-6.0), math.radians(9.0))
    frame = render_frame(flood, 10.0, position, yaw, camera, 5, pose=CameraPose(tilt_rad=tilt))
    ref = truth_reference(camera, position, yaw, frame.water_mask, tilt_rad=tilt)
    told = perceive(frame.image_bgr, 10.0, camera.fov_deg, yaw, roll_rad=tilt[0], pitch_rad=tilt[1])
    untold = perceive(frame.image_bgr, 10.0, camera.fov_deg, yaw)
    assert told.has_edge and untold.has_edge
    assert np.linalg.norm(told.midpoint_offset_en_m - ref.midpoint_en_m) < 0.05
    assert np.linalg.norm(untold.midpoint_offset_en_m - ref.midpoint_en_m) > 1.0


def test_accelerating_forward_pitches_the_nose_down_and_right_rolls_right() -> None:
    tilt = tilt_from_acceleration_rad([[2.0, 0.0, 0.0], [0.0, 2.0, 0.0]], [0.0, 0.0])
    np.testing.assert_allclose(tilt[0], [0.0, -math.atan2(2.0, 9.80665)], atol=1e-12)
    np.testing.assert_allclose(tilt[1], [math.atan2(2.0, 9.80665), 0.0], atol=1e-12)
