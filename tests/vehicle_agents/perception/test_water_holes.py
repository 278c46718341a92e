"""Floating debris: small land patches enclosed by water are water; the shore and islands of real size stay land."""

from __future__ import annotations

import numpy as np

from vehicle_agents.perception.water_holes import MAX_HOLE_AREA_M2, fill_small_land_holes

GSD_M = 0.1
"""Ground sample [m/px]: a 0.5 m² hole is 50 pixels."""


def _frame_with_shore() -> np.ndarray:
    mask = np.ones((64, 64), bool)
    mask[:, 56:] = False  # the shore, through the image's right border
    return mask


def test_a_debris_speck_inside_the_water_becomes_water() -> None:
    mask = _frame_with_shore()
    mask[20:24, 20:26] = False  # 24 px = 0.24 m²
    filled = fill_small_land_holes(mask, GSD_M)
    assert filled[20:24, 20:26].all()
    assert not filled[:, 56:].any()


def test_land_through_the_image_border_stays_land_however_small() -> None:
    mask = np.ones((64, 64), bool)
    mask[0:3, 30:33] = False  # 9 px touching the top border
    assert not fill_small_land_holes(mask, GSD_M)[0:3, 30:33].any()


def test_an_island_larger_than_the_limit_stays_land() -> None:
    mask = _frame_with_shore()
    side = int(np.ceil(np.sqrt(MAX_HOLE_AREA_M2) / GSD_M)) + 1
    mask[10 : 10 + side, 10 : 10 + side] = False
    assert not fill_small_land_holes(mask, GSD_M)[10 : 10 + side, 10 : 10 + side].any()


def test_the_limit_is_on_the_ground_not_in_pixels() -> None:
    mask = _frame_with_shore()
    mask[20:30, 20:30] = False  # 100 px: 1 m² at 0.1 m/px, 0.25 m² at 0.05 m/px
    assert not fill_small_land_holes(mask, 0.1)[20:30, 20:30].any()
    assert fill_small_land_holes(mask, 0.05)[20:30, 20:30].all()


def test_land_touching_water_only_at_a_corner_is_still_enclosed() -> None:
    mask = _frame_with_shore()
    mask[30, 30] = mask[31, 31] = False  # two pixels meeting at a corner: two 4-connected specks
    assert fill_small_land_holes(mask, GSD_M)[30:32, 30:32].all()


def test_a_frame_without_enclosed_land_is_returned_as_it_is() -> None:
    mask = _frame_with_shore()
    assert fill_small_land_holes(mask, GSD_M) is mask
    water = np.ones((16, 16), bool)
    assert fill_small_land_holes(water, GSD_M) is water
