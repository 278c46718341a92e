"""The blue cue's blueness in integers is the rounded floating-point ``B − (G + R)/2 + 128`` on every colour, and
its early rejection on ``2B − G − R`` says what the blueness would."""

from __future__ import annotations

import cv2
import numpy as np

from vehicle_agents.perception.water_mask import (
    _MAX_TWICE_WITHOUT_BLUE,
    MAX_THRESHOLD_SHIFT,
    NEUTRAL_BLUENESS,
    _blueness,
    _twice_blueness,
)


def _all_colours() -> np.ndarray:
    levels = np.arange(256, dtype=np.uint8)
    blue, green, red = np.meshgrid(levels, levels, levels, indexing="ij")
    return np.stack([blue, green, red], axis=-1).reshape(4096, 4096, 3)


def test_blueness_matches_the_floating_point_transform_on_all_colours() -> None:
    image = _all_colours()
    expected = cv2.transform(image, np.array([[1.0, -0.5, -0.5, 128.0]], np.float32))
    assert np.array_equal(_blueness(image), expected)


def test_twice_the_blueness_is_exact_and_its_rejection_matches_the_blueness_on_all_colours() -> None:
    image = _all_colours()
    twice = _twice_blueness(image)
    channels = image.astype(np.int32)
    assert np.array_equal(twice, 2 * channels[..., 0] - channels[..., 1] - channels[..., 2])
    rejected = twice <= _MAX_TWICE_WITHOUT_BLUE
    assert np.array_equal(rejected, _blueness(image) <= NEUTRAL_BLUENESS - MAX_THRESHOLD_SHIFT)
