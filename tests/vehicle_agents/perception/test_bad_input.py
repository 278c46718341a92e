"""Bad input never raises out of ``perceive``: it gives the well-defined no-measurement result."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mock_autopilot.camera.model import CameraModel
from mock_autopilot.camera.render import render_frame
from mock_autopilot.world.flood_model import ExpandingCircle
from vehicle_agents.perception.result import PerceptionResult
from vehicle_agents.perception.segmentation import perceive

GOOD = render_frame(ExpandingCircle(), 0.0, (12.0, 0.0, 10.0), 0.0, CameraModel(), seed=1).image_bgr


def is_no_measurement(result: PerceptionResult) -> bool:
    return (isinstance(result, PerceptionResult) and not result.has_edge and math.isnan(result.water_fraction)
            and not result.only_land and not result.only_water and result.midpoint_offset_en_m is None)


@pytest.mark.parametrize(
    "image",
    [
        None,
        "frame.png",
        [],
        np.zeros((0, 0, 3), np.uint8),
        np.zeros((128, 128), np.uint8),
        GOOD.astype(np.float32),
        GOOD[..., :2].copy(),
        GOOD[:5, :5],
        np.zeros((5000, 8, 3), np.uint8),
        np.zeros((128, 128, 3), np.uint8),
        np.full((128, 128, 3), 255, np.uint8),
        np.full((128, 128, 3), 128, np.uint8),
        np.full((128, 128, 3), (200, 10, 10), np.uint8),
    ],
    ids=["none", "str", "list", "empty", "grey", "float", "two-channel", "tiny", "huge", "black", "saturated",
         "flat-grey", "flat-blue"],
)
def test_unusable_images(image: object) -> None:
    assert is_no_measurement(perceive(image, 10.0, 60.0, 0.0))


@pytest.mark.parametrize(
    ("altitude_m", "fov_deg", "yaw"),
    [(float("nan"), 60.0, 0.0), (0.0, 60.0, 0.0), (-3.0, 60.0, 0.0), (float("inf"), 60.0, 0.0), (10.0, 0.0, 0.0),
     (10.0, float("nan"), 0.0), (10.0, 180.0, 0.0), (10.0, -60.0, 0.0), (10.0, 60.0, float("nan")),
     ("ten", 60.0, 0.0), (None, 60.0, 0.0)],
)
def test_unusable_geometry(altitude_m: object, fov_deg: float, yaw: float) -> None:
    assert is_no_measurement(perceive(GOOD, altitude_m, fov_deg, yaw))  # type: ignore[arg-type]


def test_the_good_frame_is_measured_and_an_alpha_channel_is_ignored() -> None:
    result = perceive(GOOD, 10.0, 60.0, 0.0)
    assert result.has_edge and 0.3 < result.water_fraction < 0.7
    with_alpha = np.dstack([GOOD, np.full(GOOD.shape[:2], 255, np.uint8)])
    np.testing.assert_allclose(perceive(with_alpha, 10.0, 60.0).midpoint_offset_en_m, result.midpoint_offset_en_m)


def test_a_mostly_saturated_frame_with_some_scene_left_is_still_no_measurement() -> None:
    blown = GOOD.copy()
    blown[:120] = 255
    assert is_no_measurement(perceive(blown, 10.0, 60.0))


def test_random_garbage_never_raises() -> None:
    rng = np.random.default_rng(0)
    for _ in range(200):
        h, w = int(rng.integers(1, 200)), int(rng.integers(1, 200))
        image = rng.integers(0, 256, (h, w, 3), dtype=np.uint8)
        if rng.random() < 0.3:
            image[:] = image.mean(axis=(0, 1)).astype(np.uint8)
        result = perceive(image, float(rng.uniform(-5, 50)), float(rng.uniform(-10, 200)), float(rng.normal()))
        assert isinstance(result, PerceptionResult)
        if result.has_edge:
            assert result.midpoint_offset_en_m is not None and np.all(np.isfinite(result.midpoint_offset_en_m))
            assert abs(float(np.linalg.norm(result.edge_normal_en)) - 1.0) < 1e-9
