"""The downward camera: geometry and orientation of the image, the truth mask, and that the picture is a real
segmentation task (textures, shoreline band, lighting, noise) rather than two flat colours (SPEC §3)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mock_autopilot.camera.model import CameraModel
from mock_autopilot.camera.render import ground_points_en_m, render_frame
from mock_autopilot.world.config import flood_model_from_config
from mock_autopilot.world.flood_model import ExpandingCircle

CIRCLE = ExpandingCircle()  # radius 12 m at t = 0, centred on the origin


def test_footprint_is_2h_tan_half_fov() -> None:
    camera = CameraModel()
    assert camera.footprint_side_m(10.0) == pytest.approx(2 * 10 * math.tan(math.radians(30.0)))
    assert camera.ground_sample_m(10.0) == pytest.approx(camera.footprint_side_m(10.0) / 128)
    assert CameraModel(160, 120).footprint_height_m(10.0) == pytest.approx(0.75 * camera.footprint_side_m(10.0))


@pytest.mark.parametrize("bad", [dict(width_px=4), dict(fov_deg=0.0), dict(fov_deg=float("nan")), dict(fov_deg=175.0)])
def test_camera_model_rejects_bad_parameters(bad: dict) -> None:
    with pytest.raises(ValueError, match="camera"):
        CameraModel(**bad)


def test_frame_shape_types_and_truth_mask_is_the_flood_at_pixel_centres() -> None:
    for camera in (CameraModel(), CameraModel(160, 120, 70.0)):
        frame = render_frame(CIRCLE, 0.0, (11.0, 3.0, 10.0), 0.4, camera, seed=2)
        assert frame.image_bgr.shape == (camera.height_px, camera.width_px, 3)
        assert frame.image_bgr.dtype == np.uint8
        assert frame.water_mask.shape == (camera.height_px, camera.width_px) and frame.water_mask.dtype == bool
        points = ground_points_en_m(camera, (11.0, 3.0, 10.0), 0.4)
        np.testing.assert_array_equal(frame.water_mask, CIRCLE.is_water(points, 0.0))
        assert 0.2 < frame.water_mask.mean() < 0.8


@pytest.mark.parametrize(
    ("yaw_deg", "water_side"),
    [(0.0, "left"), (90.0, "bottom"), (-90.0, "top"), (180.0, "right")],
)
def test_image_up_is_vehicle_forward_and_right_is_vehicle_right(yaw_deg: float, water_side: str) -> None:
    # The drone hovers over the east shore (12 m east of the centre): the water lies to its west.
    mask = render_frame(CIRCLE, 0.0, (12.0, 0.0, 10.0), math.radians(yaw_deg), CameraModel(), seed=1).water_mask
    halves = {"left": mask[:, :64], "right": mask[:, 64:], "top": mask[:64, :], "bottom": mask[64:, :]}
    assert halves[water_side].mean() > 0.9
    opposite = {"left": "right", "right": "left", "top": "bottom", "bottom": "top"}[water_side]
    assert halves[opposite].mean() < 0.1


def test_the_edge_is_at_the_image_centre_when_the_drone_is_over_it() -> None:
    mask = render_frame(CIRCLE, 0.0, (12.0, 0.0, 10.0), 0.0, CameraModel(), seed=1).water_mask
    row = mask[64]
    assert row[:63].all() and not row[65:].any()


def test_same_arguments_same_frame_and_noise_changes_between_frames() -> None:
    a = render_frame(CIRCLE, 5.0, (12.0, 0.0, 10.0), 0.0, CameraModel(), seed=4)
    b = render_frame(CIRCLE, 5.0, (12.0, 0.0, 10.0), 0.0, CameraModel(), seed=4)
    c = render_frame(CIRCLE, 5.1, (12.0, 0.0, 10.0), 0.0, CameraModel(), seed=4)
    np.testing.assert_array_equal(a.image_bgr, b.image_bgr)
    assert np.any(a.image_bgr != c.image_bgr)


def test_ground_texture_stays_put_while_the_drone_moves() -> None:
    camera = CameraModel()
    gsd = camera.ground_sample_m(10.0)
    a = render_frame(CIRCLE, 0.0, (40.0, 0.0, 10.0), 0.0, camera, seed=3).image_bgr.astype(float)
    b = render_frame(CIRCLE, 0.0, (40.0 + 16 * gsd, 0.0, 10.0), 0.0, camera, seed=3).image_bgr.astype(float)
    same_ground = np.corrcoef(a[:, 16:, 1].ravel(), b[:, :-16, 1].ravel())[0, 1]
    other_ground = np.corrcoef(a[:, 16:, 1].ravel(), a[:, :-16, 1].ravel())[0, 1]
    assert same_ground > 0.8 > other_ground


def test_the_image_is_a_real_segmentation_task() -> None:
    frame = render_frame(CIRCLE, 0.0, (12.0, 0.0, 10.0), 0.0, CameraModel(), seed=5)
    image = frame.image_bgr.astype(float)
    water, land = frame.water_mask, ~frame.water_mask
    assert image[water].std(axis=0).min() > 3.0, "water is textured and noisy"
    assert image[land].std(axis=0).min() > 5.0, "land is textured and noisy"
    # A darker wet band along the shore: land within 0.2 m of the water is much less green than land 0.6-2 m away.
    points = ground_points_en_m(CameraModel(), (12.0, 0.0, 10.0), 0.0)
    distance = np.hypot(points[..., 0], points[..., 1]) - 12.0
    green = image[..., 1]
    assert green[(distance > 0.02) & (distance < 0.2)].mean() < green[(distance > 0.6) & (distance < 2.0)].mean() - 15.0
    # Lighting: the same colour class is not equally bright in every part of the image.
    brightness = image.mean(axis=2)
    corners = [brightness[:16, 100:][land[:16, 100:]].mean(), brightness[112:, 100:][land[112:, 100:]].mean()]
    assert abs(corners[0] - corners[1]) > 0.5


def test_bad_pose_gives_a_black_frame_and_no_water() -> None:
    for position, yaw in (((float("nan"), 0.0, 10.0), 0.0), ((0.0, 0.0, 10.0), float("inf")), ((1.0, 2.0), 0.0)):
        frame = render_frame(CIRCLE, 0.0, position, yaw, CameraModel(), seed=1)
        assert not frame.image_bgr.any() and not frame.water_mask.any()


def test_every_flood_model_renders() -> None:
    for model in ("circle", "ellipse", "nonconvex", "drift", "terrain"):
        flood = flood_model_from_config({"model": model}, seed=1)
        edge = flood.boundary_en_m(30.0)[0]
        frame = render_frame(flood, 30.0, (edge[0], edge[1], 10.0), 0.0, CameraModel(), seed=1)
        assert 0.05 < frame.water_mask.mean() < 0.95, model


def test_water_over_terrain_is_shaded_by_depth_and_seen_from_the_height_above_ground() -> None:
    """The hydro flood: the pixel footprint follows the ground below the drone (what the rangefinder reads), and
    shallow water at the shore is turbid (closer to grey) while deeper water keeps the murky blue."""
    from mock_autopilot.camera.appearance import water_shading
    from mock_autopilot.camera.truth import ACCURACY_FLOODS
    from mock_autopilot.world.ground import height_above_ground_m

    flood = flood_model_from_config(ACCURACY_FLOODS["hydro"], seed=3)
    camera = CameraModel()
    ring = flood.boundary_en_m(30.0)
    heights = [height_above_ground_m(flood, (float(p[0]), float(p[1]), 10.0)) for p in ring[::7]]
    assert max(heights) - min(heights) > 0.05  # the relief is really there under the shore
    p = ring[0]
    frame = render_frame(flood, 30.0, (float(p[0]), float(p[1]), 10.0), 0.0, camera, 1)
    expected = camera.ground_sample_m(height_above_ground_m(flood, (float(p[0]), float(p[1]), 10.0)))
    assert frame.ground_sample_m == pytest.approx(expected)
    turbid, brightness = water_shading(np.array([0.02, 0.1, 0.5, 2.0], np.float32))
    assert np.all(np.diff(turbid) <= 0) and turbid[0] > 0.9 and turbid[-1] == 0.0
    assert np.all(np.diff(brightness) <= 0) and brightness[0] == 1.0 and brightness[-1] < 0.8


def test_flow_streaks_run_along_the_current_and_vanish_on_still_water() -> None:
    from mock_autopilot.camera.water_over_terrain import streaks

    points = ground_points_en_m(CameraModel(), (3.0, -2.0, 10.0), 0.0)
    assert streaks((0.0, 0.0), points[:2, :2], points.shape[:2], 1) is None
    east = streaks((0.6, 0.0), points[:2, :2], points.shape[:2], 1)  # current to the east: streaks vary across it (north), little along it
    assert east.std() > 0.02
    assert np.abs(np.diff(east, axis=1)).mean() < 0.5 * np.abs(np.diff(east, axis=0)).mean()  # image up = north
