import math

import numpy as np
import pytest

from gcs.metrics import CoverageGrid, footprint_coverage, footprint_side_m

GRID = CoverageGrid.around((0.0, 0.0), (20.0, 10.0), max_cells_per_side=402)


def all_water_east_of(x_m: float) -> np.ndarray:
    return GRID.centres_en_m()[..., 0] >= x_m


def test_footprint_side_follows_altitude_and_field_of_view() -> None:
    assert footprint_side_m(10.0, 60.0) == pytest.approx(2 * 10 * math.tan(math.radians(30)))
    assert np.array_equal(footprint_side_m([0.0, -1.0], 60.0), [0.0, 0.0])


def test_one_square_inside_a_water_box() -> None:
    water = (GRID.centres_en_m()[..., 0] >= 0) & (GRID.centres_en_m()[..., 0] <= 20) & (GRID.centres_en_m()[..., 1] >= 0) & (GRID.centres_en_m()[..., 1] <= 10)
    stats = footprint_coverage(GRID, water, [[5.0, 5.0]], [4.0])
    assert stats.flood_area_m2 == pytest.approx(200.0, rel=0.01)
    assert stats.coverage == pytest.approx(16.0 / 200.0, rel=0.03)
    assert stats.upper_bound == pytest.approx(stats.coverage)
    assert stats.overlap_efficiency == pytest.approx(1.0)


def test_overlapping_squares_and_a_square_half_on_land() -> None:
    water = all_water_east_of(10.0)
    # Two 4 m squares overlapping by half, fully in water: union 24 m², sum 32 m².
    stats = footprint_coverage(GRID, water, [[14.0, 5.0], [16.0, 5.0]], [4.0, 4.0])
    assert stats.union_water_m2 == pytest.approx(24.0, rel=0.03)
    assert stats.sum_water_m2 == pytest.approx(32.0, rel=0.03)
    assert stats.overlap_efficiency == pytest.approx(0.75, abs=0.02)
    # A square straddling the shore counts only its water half.
    half = footprint_coverage(GRID, water, [[10.0, 5.0]], [4.0])
    assert half.sum_water_m2 == pytest.approx(8.0, rel=0.05)
    assert half.coverage <= half.upper_bound + 1e-12


def test_ignored_footprints_and_a_dry_world() -> None:
    water = all_water_east_of(10.0)
    none = footprint_coverage(GRID, water, [[15.0, 5.0], [np.nan, 0.0]], [0.0, 4.0])
    assert none.coverage == 0.0 and math.isnan(none.overlap_efficiency)
    dry = footprint_coverage(GRID, np.zeros_like(water), [[15.0, 5.0]], [4.0])
    assert math.isnan(dry.coverage)


def test_yaw_aligned_square_keeps_its_area_and_turns_its_corners() -> None:
    water = all_water_east_of(0.0)
    aligned = footprint_coverage(GRID, water, [[10.0, 5.0]], [4.0], yaw_enu_rad=[0.0])
    turned = footprint_coverage(GRID, water, [[10.0, 5.0]], [4.0], yaw_enu_rad=[math.pi / 4])
    assert aligned.union_water_m2 == pytest.approx(16.0, rel=0.03)
    assert turned.union_water_m2 == pytest.approx(16.0, rel=0.03)
    # A diamond reaches 2.83 m east of its centre, an axis-aligned square only 2 m.
    shore = all_water_east_of(12.5)
    assert footprint_coverage(GRID, shore, [[10.0, 5.0]], [4.0], yaw_enu_rad=[math.pi / 4]).sum_water_m2 > 0.0
    assert footprint_coverage(GRID, shore, [[10.0, 5.0]], [4.0]).sum_water_m2 == 0.0
