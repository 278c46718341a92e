"""``flood_model_from_config``: every scenario's [flood] table builds, and bad tables give one error naming
the field."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from gcs.scenario import SCENARIO_DIR, load_scenario
from mock_autopilot.world.config import FloodConfigError, flood_model_from_config
from mock_autopilot.world.drift import DriftingFlood
from mock_autopilot.world.ellipse import GrowingEllipse
from mock_autopilot.world.flood_model import ExpandingCircle
from mock_autopilot.world.nonconvex import NonConvexFlood
from mock_autopilot.world.terrain import TerrainFlood

SCENARIOS = SCENARIO_DIR


HYDRO = ("breach", "river", "pluvial")
"""Shipped hydro scenarios: each computes a shallow-water run the first time (tens of seconds), so they are built in
tests/mock_autopilot/world/test_hydro.py's slow test."""


@pytest.mark.parametrize("path", [p for p in sorted(SCENARIOS.glob("*.toml")) if p.stem not in HYDRO], ids=lambda p: p.stem)
def test_every_shipped_scenario_flood_table_builds(path: Path) -> None:
    scenario = load_scenario(str(path))
    flood = flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
    assert flood.area_m2(0.0) > 0.0
    assert flood.is_water(flood.centroid_en_m(0.0)[None, :], 0.0).tolist() == [True]


def test_models_by_name() -> None:
    assert isinstance(flood_model_from_config({"model": "circle"}), ExpandingCircle)
    assert isinstance(flood_model_from_config({"model": "ellipse"}), GrowingEllipse)
    assert isinstance(flood_model_from_config({"model": "nonconvex"}), NonConvexFlood)
    assert isinstance(flood_model_from_config({"model": "drift", "shape": "ellipse"}), DriftingFlood)
    assert isinstance(flood_model_from_config({"model": "terrain"}), TerrainFlood)


def test_nonconvex_phase_is_drawn_from_the_seed_unless_given() -> None:
    a = flood_model_from_config({"model": "nonconvex"}, seed=1)
    b = flood_model_from_config({"model": "nonconvex"}, seed=2)
    c = flood_model_from_config({"model": "nonconvex"}, seed=1)
    assert isinstance(a, NonConvexFlood) and isinstance(b, NonConvexFlood) and isinstance(c, NonConvexFlood)
    assert a.phase_rad == c.phase_rad != b.phase_rad
    d = flood_model_from_config({"model": "nonconvex", "phase_rad": 0.7}, seed=1)
    assert isinstance(d, NonConvexFlood) and d.phase_rad == 0.7


def test_the_values_of_the_table_are_used() -> None:
    flood = flood_model_from_config({"model": "circle", "center_en_m": [3, 4], "radius_start_m": 5, "radius_end_m": 7,
                                     "growth_duration_s": 10})
    assert isinstance(flood, ExpandingCircle)
    assert flood.radius_m(5.0) == pytest.approx(6.0)
    np.testing.assert_allclose(flood.centroid_en_m(0.0), [3.0, 4.0])


@pytest.mark.parametrize(
    ("table", "field"),
    [
        ({"model": "hexagon"}, "flood.model"),
        ({"model": 3}, "flood.model"),
        ({"model": "circle", "radius_start_m": -1.0}, "flood.radius_start_m"),
        ({"model": "circle", "radius_end_m": 0}, "flood.radius_end_m"),
        ({"model": "circle", "radius_start_m": 16.0, "radius_end_m": 12.0}, "flood.radius_end_m"),
        ({"model": "circle", "radius_start_m": "big"}, "flood.radius_start_m"),
        ({"model": "circle", "radius_start_m": float("nan")}, "flood.radius_start_m"),
        ({"model": "circle", "growth_duration_s": -5}, "flood.growth_duration_s"),
        ({"model": "circle", "center_en_m": [1.0]}, "flood.center_en_m"),
        ({"model": "circle", "radius": 12}, "flood.radius"),
        ({"model": "ellipse", "semi_axes_start_m": [14, -9]}, "flood.semi_axes_start_m"),
        ({"model": "ellipse", "semi_axes_start_m": [14, 9], "semi_axes_end_m": [19, 8]}, "flood.semi_axes_end_m"),
        ({"model": "nonconvex", "amplitude_3": 0.6, "amplitude_5": 0.5}, "flood.amplitude_5"),
        ({"model": "drift", "shape": "terrain"}, "flood.shape"),
        ({"model": "drift", "velocity_en_mps": [1, "x"]}, "flood.velocity_en_mps"),
        ({"model": "terrain", "level_start_m": 2.0, "level_end_m": 1.0}, "flood.level_end_m"),
        ({"model": "terrain", "level_start_m": -1.0}, "flood.level_start_m"),
        ({"model": "terrain", "level_end_m": 40.0}, "flood.level_end_m"),
        ({"model": "terrain", "roughness": 2.0}, "flood.roughness"),
        ({"model": "terrain", "cell_m": 0.001}, "flood.cell_m"),
        ({"model": "terrain", "dem_path": "no/such/dem.png"}, "flood.dem_path"),
    ],
)
def test_bad_tables_name_the_field(table: dict, field: str) -> None:
    with pytest.raises(FloodConfigError) as info:
        flood_model_from_config(table)
    message = str(info.value)
    assert message.startswith(f"{field}:"), message
    assert "\n" not in message
    assert isinstance(info.value, ValueError)


@pytest.mark.parametrize(("table", "message"), [
    ({"model": "circle", "radius_ends_m": 20}, "flood.radius_ends_m: unknown key for model 'circle' "
                                               "(did you mean flood.radius_end_m?)"),
    ({"model": "drift", "velocity_mps": [1, 0]}, "flood.velocity_mps: unknown key for model 'drift' "
                                                "(did you mean flood.velocity_en_mps?)"),
    ({"model": "circle", "nonsense": 3}, "flood.nonsense: unknown key for model 'circle' (known: center_en_m, "
                                         "growth_duration_s, model, radius_end_m, radius_start_m)"),
])
def test_unknown_keys_name_the_closest_known_key(table: dict, message: str) -> None:
    with pytest.raises(FloodConfigError) as info:
        flood_model_from_config(table)
    assert str(info.value) == message


def test_not_a_table() -> None:
    with pytest.raises(FloodConfigError, match=r"^flood: must be a table"):
        flood_model_from_config(["circle"])  # type: ignore[arg-type]


def test_source_outside_the_dem(tmp_path: Path) -> None:
    assert cv2.imwrite(str(tmp_path / "dem.png"), np.full((32, 32), 1000, np.uint16))
    table = {"model": "terrain", "dem_path": str(tmp_path / "dem.png"), "dem_center_en_m": [0.0, 0.0],
             "source_en_m": [500.0, 0.0]}
    with pytest.raises(FloodConfigError, match=r"^flood\.source_en_m: .*outside the terrain"):
        flood_model_from_config(table)


def test_a_16_bit_tiff_dem_builds_and_floods_the_basin(tmp_path: Path) -> None:
    rows, cols = np.mgrid[0:64, 0:64]
    heights_m = 0.01 * ((cols - 31.5) ** 2 + (rows - 31.5) ** 2)  # a bowl, 1 m cells, lowest at the centre
    assert cv2.imwrite(str(tmp_path / "dem.tif"), np.round(heights_m * 100).astype(np.uint16))
    table = {"model": "terrain", "dem_path": "dem.tif", "dem_cell_m": 1.0, "dem_height_scale_m": 0.01,
             "level_start_m": 1.0, "level_end_m": 4.0}
    flood = flood_model_from_config(table, base_dir=tmp_path)
    assert isinstance(flood, TerrainFlood)
    # Water below 1 m in a bowl of 0.01 r² is a disc of radius 10 m, then 20 m at 4 m.
    assert flood.area_m2(0.0) == pytest.approx(np.pi * 100.0, rel=0.05)
    assert flood.area_m2(60.0) == pytest.approx(np.pi * 400.0, rel=0.05)


def test_dem_that_is_not_a_grey_image(tmp_path: Path) -> None:
    assert cv2.imwrite(str(tmp_path / "colour.png"), np.zeros((32, 32, 3), np.uint8))
    (tmp_path / "text.png").write_text("not an image")
    for name in ("colour.png", "text.png"):
        with pytest.raises(FloodConfigError, match=r"^flood\.dem_path: "):
            flood_model_from_config({"model": "terrain", "dem_path": name}, base_dir=tmp_path)
