"""The tracked edge offset's median: numpy's value, bit for bit, without numpy's generic path."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vehicle_agents.control.vision_tracking import median


@pytest.mark.parametrize("count", [1, 2, 3, 4, 7, 24, 63, 64])
def test_median_is_numpys_bit_for_bit(count: int) -> None:
    rng = np.random.default_rng(count)
    for scale in (1e-3, 1.0, 1e3):
        values = rng.normal(size=count) * scale
        assert median(values) == float(np.median(values))


def test_median_of_values_with_a_nan_is_nan() -> None:
    assert math.isnan(median(np.array([1.0, math.nan, 2.0])))
