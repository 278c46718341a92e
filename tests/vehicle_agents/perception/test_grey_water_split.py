"""Which small classes of a grey-water split count as an edge (pure function on 0/1 masks)."""

from __future__ import annotations

import numpy as np

from vehicle_agents.perception.grey_water import _small_class_reaches_side

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
