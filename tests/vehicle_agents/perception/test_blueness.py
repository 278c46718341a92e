"""The blue cue's blueness in integers is the rounded floating-point ``B − (G + R)/2 + 128`` on every colour."""

from __future__ import annotations

import cv2
import numpy as np

from vehicle_agents.perception.water_mask import _blueness


def test_blueness_matches_the_floating_point_transform_on_all_colours() -> None:
    levels = np.arange(256, dtype=np.uint8)
    blue, green, red = np.meshgrid(levels, levels, levels, indexing="ij")
    image = np.stack([blue, green, red], axis=-1).reshape(4096, 4096, 3)
    expected = cv2.transform(image, np.array([[1.0, -0.5, -0.5, 128.0]], np.float32))
    assert np.array_equal(_blueness(image), expected)
