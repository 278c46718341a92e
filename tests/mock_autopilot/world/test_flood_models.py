"""Every flood model answers the FloodModel protocol consistently: water inside its own boundary, area and centroid
of that boundary, growth over time, determinism (SPEC §3)."""

from __future__ import annotations

import math
from pathlib import Path

import cv2
import numpy as np
import pytest

from mock_autopilot.world.config import flood_model_from_config
from mock_autopilot.world.drift import DriftingFlood
from mock_autopilot.world.ellipse import GrowingEllipse
from mock_autopilot.world.flood_model import ExpandingCircle, FloodModel
from mock_autopilot.world.heightmap import Heightmap
from mock_autopilot.world.nonconvex import NonConvexFlood
from mock_autopilot.world.terrain import TerrainFlood

SCENARIO_TABLES = {
    "circle": {"model": "circle"},
    "ellipse": {"model": "ellipse", "semi_axes_start_m": [14.0, 9.0], "semi_axes_end_m": [19.0, 12.0],
                "orientation_deg": 20.0},
    "nonconvex": {"model": "nonconvex", "phase_rad": 0.7},
    "drift": {"model": "drift", "shape": "nonconvex", "velocity_en_mps": [0.12, 0.09]},
    "terrain": {"model": "terrain", "level_start_m": 1.0, "level_end_m": 2.0, "terrain_size_m": 120.0, "cell_m": 0.5,
                "basin_scale_m": 30.0, "relief_m": 4.0, "roughness": 0.5, "terrain_seed": 7},
}


def ring_area_centroid(ring: np.ndarray) -> tuple[float, np.ndarray]:
    x, y = ring[:, 0], ring[:, 1]
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = 0.5 * cross.sum()
    cx = ((x + np.roll(x, -1)) * cross).sum() / (6 * area)
    cy = ((y + np.roll(y, -1)) * cross).sum() / (6 * area)
    return float(area), np.array([cx, cy])


@pytest.fixture(scope="module", params=sorted(SCENARIO_TABLES))
def flood(request: pytest.FixtureRequest) -> FloodModel:
    return flood_model_from_config(SCENARIO_TABLES[request.param], seed=3)


@pytest.mark.parametrize("t_s", [0.0, 30.0, 60.0])
def test_boundary_is_a_ccw_ring_whose_area_and_centroid_match(flood: FloodModel, t_s: float) -> None:
    ring = flood.boundary_en_m(t_s)
    assert ring.ndim == 2 and ring.shape[1] == 2 and ring.shape[0] >= 16
    area, centroid = ring_area_centroid(ring)
    assert area > 0.0, "boundary must be counter-clockwise"
    # Terrain islands are excluded from the area but not from the outer ring: allow a little more there.
    tolerance = 0.06 if isinstance(flood, TerrainFlood) else 0.01
    assert flood.area_m2(t_s) == pytest.approx(area, rel=tolerance)
    if not isinstance(flood, TerrainFlood):
        np.testing.assert_allclose(flood.centroid_en_m(t_s), centroid, atol=0.05)
    assert isinstance(flood, FloodModel)


@pytest.mark.parametrize("t_s", [0.0, 45.0])
def test_water_just_inside_and_land_just_outside_the_boundary(flood: FloodModel, t_s: float) -> None:
    ring = flood.boundary_en_m(t_s)
    along = np.roll(ring, -1, axis=0) - np.roll(ring, 1, axis=0)
    outward = np.stack([along[:, 1], -along[:, 0]], axis=-1)  # right of the direction of travel on a CCW ring
    length = np.linalg.norm(outward, axis=1)
    ring, outward = ring[length > 0], outward[length > 0] / length[length > 0, None]  # a traced ring may fold back
    inside = flood.is_water(ring - 0.3 * outward, t_s)
    outside = flood.is_water(ring + 0.3 * outward, t_s)
    # The terrain ring is traced at a finite resolution and its shore has features finer than 0.3 m in places.
    need = 0.95 if isinstance(flood, TerrainFlood) else 0.999
    assert inside.mean() >= need
    assert (~outside).mean() >= need


def test_is_water_keeps_the_shape_of_any_point_array(flood: FloodModel) -> None:
    pts = np.zeros((3, 5, 7, 2))
    assert flood.is_water(pts, 10.0).shape == (3, 5, 7)
    assert flood.is_water(np.zeros((0, 2)), 10.0).shape == (0,)
    assert flood.is_water(np.array([[1e6, 1e6]]), 10.0).tolist() == [False]


def test_floods_grow_and_hold_after_the_growth_period(flood: FloodModel) -> None:
    areas = [flood.area_m2(t) for t in (-5.0, 0.0, 20.0, 40.0, 60.0, 90.0)]
    assert areas[0] == pytest.approx(areas[1])
    assert areas[1] < areas[2] < areas[3] < areas[4]
    assert areas[5] == pytest.approx(areas[4])


def test_same_table_and_seed_give_the_same_flood() -> None:
    for name, table in SCENARIO_TABLES.items():
        a = flood_model_from_config(table, seed=5)
        b = flood_model_from_config(table, seed=5)
        np.testing.assert_array_equal(a.boundary_en_m(17.0), b.boundary_en_m(17.0), err_msg=name)


def test_circle_is_the_papers_12_to_16_m_flood() -> None:
    circle = ExpandingCircle()
    assert circle.radius_m(0.0) == 12.0 and circle.radius_m(30.0) == 14.0 and circle.radius_m(60.0) == 16.0
    assert circle.is_water([[13.9, 0.0], [14.1, 0.0]], 30.0).tolist() == [True, False]


def test_ellipse_axes_grow_at_their_own_rates_along_its_orientation() -> None:
    ellipse = GrowingEllipse((5.0, -2.0), (10.0, 4.0), (20.0, 5.0), orientation_deg=90.0, growth_duration_s=10.0)
    assert ellipse.semi_axes_m(5.0) == pytest.approx((15.0, 4.5))
    # The a axis points north: 14.9 m north is water at t = 5, 14.9 m east is not.
    assert ellipse.is_water([[5.0, 12.9], [5.0 + 4.4, -2.0], [5.0 + 4.6, -2.0]], 5.0).tolist() == [True, True, False]
    assert ellipse.area_m2(10.0) == pytest.approx(math.pi * 100.0)


def test_nonconvex_radius_follows_spec_formula_and_has_bays() -> None:
    flood = NonConvexFlood(radius_start_m=12.0, radius_end_m=16.0, amplitude_3=0.2, amplitude_5=0.1, phase_rad=0.7)
    theta = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)
    expected = 14.0 * (1 + 0.2 * np.cos(3 * theta) + 0.1 * np.cos(5 * theta + 0.7))
    dirs = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    assert flood.is_water(dirs * (expected - 0.01)[:, None], 30.0).all()
    assert not flood.is_water(dirs * (expected + 0.01)[:, None], 30.0).any()
    ring = flood.boundary_en_m(30.0)
    hull_area = cv2.contourArea(cv2.convexHull(ring.astype(np.float32)))
    assert flood.area_m2(30.0) < 0.95 * hull_area, "the flood must be clearly non-convex"


def test_drift_moves_the_whole_flood_then_stops() -> None:
    flood = DriftingFlood(ExpandingCircle(), velocity_en_mps=(0.5, -0.25), drift_duration_s=20.0)
    np.testing.assert_allclose(flood.centroid_en_m(10.0), [5.0, -2.5])
    np.testing.assert_allclose(flood.centroid_en_m(100.0), [10.0, -5.0])
    assert flood.is_water([[10.0 + 15.9, -5.0]], 100.0).tolist() == [True]
    assert flood.is_water([[-15.0, 0.0]], 100.0).tolist() == [False]
    assert flood.area_m2(100.0) == pytest.approx(ExpandingCircle().area_m2(100.0))


def _two_basins_with_an_island() -> Heightmap:
    """40 x 40 cells of 1 m: a bowl around (0, 0) with a 1 m high island at (3, 3), and a separate deeper pit at
    (-14, -14) behind a 3 m ridge."""
    rows, cols = np.mgrid[0:40, 0:40]
    east = cols + 0.5 - 20.0
    north = 20.0 - (rows + 0.5)
    heights = 0.01 * (east**2 + north**2)
    heights[(np.abs(east - 3.0) < 1.0) & (np.abs(north - 3.0) < 1.0)] = 1.0
    heights[(east < -9) & (north < -9)] = -1.0
    heights[(np.abs(east + 9.5) < 1) & (north < -8.5)] = 3.0
    heights[(np.abs(north + 9.5) < 1) & (east < -8.5)] = 3.0
    return Heightmap(heights.astype(np.float32), 1.0, (0.0, 0.0))


def test_terrain_floods_only_the_sources_component_and_keeps_islands_dry() -> None:
    flood = TerrainFlood(_two_basins_with_an_island(), (0.0, 0.0), 0.5, 0.9, 10.0)
    assert flood.is_water([[0.0, 0.0], [5.0, 0.0]], 0.0).tolist() == [True, True]
    assert flood.is_water([[3.0, 3.0]], 10.0).tolist() == [False], "the island stays dry"
    assert flood.is_water([[-15.0, -15.0]], 10.0).tolist() == [False], "the pit behind the ridge is not connected"
    assert flood.is_water([[8.0, 0.0]], 0.0).tolist() == [False]
    assert flood.is_water([[8.0, 0.0]], 10.0).tolist() == [True]
    # Area of the bowl below 0.9 m (r < ~9.5 m) minus the 4 m² island.
    assert flood.area_m2(10.0) == pytest.approx(math.pi * 90.0 - 4.0, rel=0.05)


def test_terrain_from_a_16_bit_dem_png(tmp_path: Path) -> None:
    heights = _two_basins_with_an_island().heights_m
    counts = np.round((heights + 2.0) * 1000.0).astype(np.uint16)
    assert cv2.imwrite(str(tmp_path / "dem.png"), counts)
    table = {"model": "terrain", "dem_path": "dem.png", "dem_cell_m": 1.0, "dem_height_scale_m": 0.001,
             "dem_height_offset_m": -2.0, "level_start_m": 0.5, "level_end_m": 0.9, "growth_duration_s": 10.0}
    flood = flood_model_from_config(table, base_dir=tmp_path)
    reference = TerrainFlood(_two_basins_with_an_island(), (0.0, 0.0), 0.5, 0.9, 10.0)
    assert flood.area_m2(10.0) == pytest.approx(reference.area_m2(10.0), rel=0.01)
    assert flood.is_water([[3.0, 3.0], [-15.0, -15.0], [6.0, 0.0]], 10.0).tolist() == [False, False, True]


def test_fractal_terrain_is_one_irregular_water_body_with_islands_for_some_seeds() -> None:
    table = dict(SCENARIO_TABLES["terrain"])
    grid = np.stack(np.meshgrid(np.arange(-40.0, 40.0, 0.25), np.arange(40.0, -40.0, -0.25)), axis=-1)
    seeds_with_islands = 0
    for seed in range(4):
        table["terrain_seed"] = seed
        flood = flood_model_from_config(table)
        ring = flood.boundary_en_m(60.0)
        ring_area, _ = ring_area_centroid(ring)
        assert ring_area < 0.97 * cv2.contourArea(cv2.convexHull(ring.astype(np.float32))), "shores are irregular"
        for t_s in (0.0, 60.0):
            water = flood.is_water(grid, t_s).view(np.uint8)
            n_labels, _ = cv2.connectedComponents(water, connectivity=4)
            assert n_labels - 1 == 1, "only the source's component is flooded"
            contours, hierarchy = cv2.findContours(water, cv2.RETR_CCOMP, cv2.CHAIN_APPROX_SIMPLE)
            holes = [c for c, h in zip(contours, hierarchy[0]) if h[3] >= 0 and cv2.contourArea(c) > 4.0]
            seeds_with_islands += bool(holes)
    assert seeds_with_islands >= 1


def test_a_single_points_grid_coordinates_are_the_arrays_to_the_last_bit() -> None:
    grid = Heightmap(np.zeros((37, 52), np.float32), 0.7, (3.25, -11.5))
    rng = np.random.default_rng(5)
    for east, north in rng.uniform(-40.0, 40.0, (200, 2)).tolist():
        col, row = grid.grid_coordinates(np.array([east, north]))
        assert grid.point_coordinates(east, north) == (float(col), float(row))
