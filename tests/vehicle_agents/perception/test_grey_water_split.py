"""Which small classes of a grey-water split count as an edge (pure function on 0/1 masks); the minimum-error
threshold and the texture medians against direct per-level computations."""

from __future__ import annotations

import numpy as np

from vehicle_agents.perception.grey_water import (
    _COLOUR_CUES,
    SCORE_SIGNS,
    TEXTURE_LEVELS_PER_UNIT,
    TEXTURE_OFFSET,
    _small_class_reaches_side,
    _texture_medians,
    minimum_error_threshold,
)
from vehicle_agents.perception.shore import COLOUR_SIGNS

SIZE = 96


def test_a_small_class_counts_only_when_it_reaches_a_side_of_the_frame() -> None:
    water = np.zeros((SIZE, SIZE), np.uint8)
    water[40:48, 40:48] = 1  # a blob wholly inside
    assert not _small_class_reaches_side(water, float(water.mean()))
    water[40:48, 0:6] = 1  # and a sliver at the left side
    assert _small_class_reaches_side(water, float(water.mean()))
    land = np.ones((SIZE, SIZE), np.uint8)
    land[50:56, 50:56] = 0  # an island wholly inside the water
    assert not _small_class_reaches_side(land, float(land.mean()))
    land[-3:, 20:30] = 0  # land reaching the bottom side
    assert _small_class_reaches_side(land, float(land.mean()))


def _direct_costs(values: np.ndarray) -> dict[int, float]:
    """Kittler-Illingworth's cost of every level that leaves both classes a spread, from the values themselves."""
    values = values.astype(np.float64)
    least = 0.002 * values.size
    costs = {}
    for level in range(256):
        low, high = values[values <= level], values[values > level]
        if low.size <= least or high.size <= least or low.var() <= 0.5 or high.var() <= 0.5:
            continue
        costs[level] = low.size * np.log(low.var() / low.size ** 2) + high.size * np.log(high.var() / high.size ** 2)
    return costs


def test_the_minimum_error_threshold_is_the_level_of_least_cost() -> None:
    rng = np.random.default_rng(5)
    for _ in range(40):
        sizes = rng.integers(50, 2000, 2)
        values = np.concatenate([rng.normal(rng.uniform(20, 230), rng.uniform(2, 30), size) for size in sizes])
        score8 = np.clip(np.round(values), 0, 255).astype(np.uint8).reshape(1, -1)
        costs = _direct_costs(score8.ravel())
        least = min(costs.values())
        assert costs[minimum_error_threshold(score8)] <= least + 1e-9 * abs(least)


def test_a_flat_image_has_no_minimum_error_threshold() -> None:
    assert minimum_error_threshold(np.full((16, 16), 77, np.uint8)) is None


def test_texture_medians_are_the_classes_median_levels() -> None:
    rng = np.random.default_rng(6)
    texture8 = rng.integers(40, 200, (64, 64), dtype=np.uint8)
    high = np.where(rng.random((64, 64)) < 0.3, 255, 0).astype(np.uint8)
    medians = _texture_medians(texture8, high)

    def median_level(values: np.ndarray) -> float:
        level = np.sort(values)[(values.size - 1) // 2]  # the lower median: the first level holding half the values
        return level / TEXTURE_LEVELS_PER_UNIT - TEXTURE_OFFSET

    expected = (median_level(texture8[high == 255]), median_level(texture8[high == 0]), median_level(texture8.ravel()))
    assert medians == expected


def test_the_colour_score_weighs_its_cues_with_the_split_s_signs() -> None:
    assert np.array_equal(SCORE_SIGNS[_COLOUR_CUES], COLOUR_SIGNS)
