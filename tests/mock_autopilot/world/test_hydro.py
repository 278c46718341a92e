"""The hydrodynamic flood: water balance, the on-disk cache, determinism, the caged component and bad tables."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from gcs.metrics.flood_extent import flood_clock, flood_extent_summary
from mock_autopilot.world import hydro_cache
from mock_autopilot.world.config import FloodConfigError, flood_model_from_config
from mock_autopilot.world.hydro import HydroFlood
from mock_autopilot.world.hydro_cache import cached_run, forget_memory, run_key
from mock_autopilot.world.hydro_solver import HydroRun, run_anuga
from mock_autopilot.world.hydro_spec import BoundaryKind, Hydrograph, HydroSpec, Source, SourceKind
from mock_autopilot.world.landforms import Landform, LandformSpec, landform_heightmap

R, O = BoundaryKind.REFLECTIVE, BoundaryKind.OUTFLOW
SMALL = LandformSpec(Landform.FARMLAND, size_m=40.0, cell_m=0.5, relief_m=0.05, slope=0.01, slope_toward_deg=0.0,
                     hedges=1, ditches=1)


def _spec(boundaries: tuple[BoundaryKind, ...] = (R, R, R, R), rain: float = 0.0, end_s: float = 30.0) -> HydroSpec:
    source = Source(SourceKind.POINT, ((12.0, 0.0),), Hydrograph((0.0, 5.0, 30.0), (0.0, 0.6, 0.4)), 2.0)
    return HydroSpec(2.0, 0.04, (source,), rain, 20.0, boundaries, end_s, 2.0)  # type: ignore[arg-type]


@pytest.fixture(autouse=True)
def _cache_in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(hydro_cache.CACHE_ENV, str(tmp_path / "cache"))
    forget_memory()


def test_volume_in_equals_volume_on_the_grid_plus_outflow_within_2_percent() -> None:
    """Closed box, a box draining east, and rain on top: the hydrograph's and the rain's integral, computed here
    independently of the solver, against the water on the raster plus what left over the edges."""
    heightmap = landform_heightmap(SMALL, 4)
    for boundaries, rain, end_s in (((R, R, R, R), 0.0, 30.0), ((R, R, O, R), 0.0, 90.0), ((R, R, O, O), 60.0, 60.0)):
        spec = _spec(boundaries, rain, end_s)
        run = run_anuga(spec, heightmap)
        side_m = run.depth_m.shape[1] * run.cell_m
        expected = spec.volume_in_m3(float(run.times_s[-1]), side_m * side_m)
        on_raster = float(run.depth_m[-1].sum()) * run.cell_m ** 2
        assert abs(on_raster + run.volume_out_m3[-1] - expected) <= 0.02 * expected, (boundaries, rain)
        if O in boundaries and rain == 0.0:
            assert run.volume_out_m3[-1] > 0.05 * expected  # the outflow edge really drained water


def test_the_same_inputs_give_the_same_rasters_and_key() -> None:
    heightmap = landform_heightmap(SMALL, 4)
    a, b = run_anuga(_spec(), heightmap), run_anuga(_spec(), heightmap)
    assert np.array_equal(a.depth_m, b.depth_m) and np.array_equal(a.times_s, b.times_s)
    assert run_key(_spec(), heightmap, "x") == run_key(_spec(), landform_heightmap(SMALL, 4), "x")
    assert run_key(_spec(), heightmap, "x") != run_key(_spec(), landform_heightmap(SMALL, 5), "x")
    assert run_key(_spec(), heightmap, "x") != run_key(_spec(rain=1.0), heightmap, "x")


def test_cache_miss_then_hit_then_corrupt_file_is_recomputed(tmp_path: Path) -> None:
    heightmap = landform_heightmap(SMALL, 4)
    calls: list[HydroRun] = []

    def compute() -> HydroRun:
        calls.append(run_anuga(_spec(), heightmap))
        return calls[-1]

    folder = tmp_path / "c"
    first, computed = cached_run("k1", compute, folder)
    assert computed and len(calls) == 1 and (folder / "k1.npz").is_file()
    forget_memory()
    again, computed = cached_run("k1", compute, folder)
    assert not computed and len(calls) == 1 and np.array_equal(again.depth_m, first.depth_m)
    for damage in (b"not a zip file", (folder / "k1.npz").read_bytes()[:500]):
        forget_memory()
        (folder / "k1.npz").write_bytes(damage)
        repaired, computed = cached_run("k1", compute, folder)
        assert computed and np.array_equal(repaired.depth_m, first.depth_m)
    forget_memory()
    (folder / "k1.npz").rename(folder / "k2.npz")
    _, computed = cached_run("k2", compute, folder)  # a file whose stored key is another key's: not trusted
    assert computed
    assert not list(folder.glob("*.tmp"))


_CHILD = textwrap.dedent("""
    import hashlib, sys
    from mock_autopilot.world import hydro_cache
    from mock_autopilot.world.config import flood_model_from_config
    calls = []
    original = hydro_cache.cached_run
    def spy(key, compute, directory=None):
        run, computed = original(key, compute, directory)
        calls.append(computed)
        return run, computed
    import mock_autopilot.world.hydro_config as hc
    hc.cached_run = spy
    flood = flood_model_from_config({TABLE!r}, seed=3)
    print(int(calls[0]), hashlib.sha256(flood.run.depth_m.tobytes()).hexdigest())
""")


def test_two_processes_computing_at_once_compute_once_and_agree(tmp_path: Path) -> None:
    table = {"model": "hydro", "landform": "farmland", "terrain_size_m": 40.0, "mesh_cell_m": 2.0, "run_s": 20.0,
             "sources": [{"kind": "point", "at_en_m": [0.0, 0.0], "hydrograph_t_s": [0.0], "hydrograph_m3ps": [0.5]}]}
    env = {**os.environ, hydro_cache.CACHE_ENV: str(tmp_path / "shared")}
    script = _CHILD.replace("{TABLE!r}", repr(table))
    children = [subprocess.Popen([sys.executable, "-c", script], env=env, stdout=subprocess.PIPE, text=True)
                for _ in range(2)]
    outputs = [c.communicate(timeout=120)[0].split() for c in children]
    assert [c.returncode for c in children] == [0, 0]
    assert sorted(int(o[0]) for o in outputs) == [0, 1]  # one computed, the other waited and read
    assert outputs[0][1] == outputs[1][1]
    assert len(list((tmp_path / "shared").glob("*.npz"))) == 1 and not list((tmp_path / "shared").glob("*.tmp"))


def _table(**changes: object) -> dict[str, object]:
    table: dict[str, object] = {
        "model": "hydro", "landform": "farmland", "terrain_size_m": 40.0, "mesh_cell_m": 2.0, "run_s": 40.0,
        "start_s": 10.0, "time_scale": 2.0,
        "sources": [{"kind": "point", "at_en_m": [0.0, 0.0], "hydrograph_t_s": [0.0], "hydrograph_m3ps": [0.5]}]}
    table.update(changes)
    return table


def test_the_flood_answers_vectorised_with_a_caged_component_and_time_scale() -> None:
    flood = flood_model_from_config(_table(), seed=3)
    assert isinstance(flood, HydroFlood)
    assert flood.hydraulic_time_s(0.0) == 10.0 and flood.hydraulic_time_s(5.0) == 20.0
    assert flood.hydraulic_time_s(1e6) == 40.0
    assert flood.area_m2(0.0) < flood.area_m2(10.0) <= flood.wet_area_m2(10.0) + 1e-9
    ring = flood.boundary_en_m(10.0)
    pts = np.stack(np.meshgrid(np.linspace(-20, 20, 41), np.linspace(-20, 20, 41)), axis=-1)
    wet = flood.is_water(pts, 10.0)
    assert wet.shape == (41, 41) and wet[20, 20] and not wet[0, 0]
    assert np.array_equal(wet, flood.depth_m(pts, 10.0) > 0.02)
    assert flood.is_water(np.array([[0.0, 0.0]]), 10.0).tolist() == [True]  # the source is in the caged water
    assert np.all(ring.min(axis=0) <= flood.centroid_en_m(10.0)) and np.all(flood.centroid_en_m(10.0) <= ring.max(axis=0))
    assert flood.is_water(ring, 10.0).mean() >= 0.9  # ring vertices are the centres of the outermost wet pixels


def test_every_result_reports_the_flood_clock() -> None:
    hydro = flood_model_from_config(_table(), seed=3)
    summary = flood_extent_summary(hydro, 0.0, 10.0)
    assert (summary["flood_time_scale"], summary["flood_hydraulic_start_s"]) == (2.0, 10.0)
    circle = flood_model_from_config({"model": "circle"}, seed=3)
    assert all(math.isnan(v) for v in flood_clock(circle).values())


@pytest.mark.parametrize(("changes", "field"), [
    ({"sources": [{"kind": "point", "hydrograph_t_s": [0.0], "hydrograph_m3ps": [-1.0]}]},
     "flood.sources[0].hydrograph_m3ps"),
    ({"sources": [{"kind": "pipe"}]}, "flood.sources[0].kind"),
    ({"sources": [{"kind": "line", "line_en_m": [[0.0, 0.0]]}]}, "flood.sources[0].line_en_m"),
    ({"sources": [{"kind": "point", "at_en_m": [500.0, 0.0]}]}, "flood.sources[0]"),
    ({"dem_path": "missing.png"}, "flood.dem_path"),
    ({"boundary": "sticky"}, "flood.boundary"),
    ({"manning_n": -0.1}, "flood.manning_n"),
    ({"landform": "moon"}, "flood.landform"),
    ({"wet_depth_m": 0.0}, "flood.wet_depth_m"),
    ({"sources": [], "rain_mm_per_h": 0.0}, "flood.sources"),
    ({"rain_mm": 3.0}, "flood.rain_mm"),
])
def test_bad_tables_name_the_field(changes: dict[str, object], field: str) -> None:
    with pytest.raises(FloodConfigError, match=rf"^{field.replace('[', '.').replace(']', '.')}"):
        flood_model_from_config(_table(**changes), seed=1)


@pytest.mark.parametrize(("flood_lines", "field"), [
    ('dem_path = "dem.png"\n[[flood.sources]]\nkind = "point"', "flood.dem_path"),
    # The same mapping for the other two (their messages are checked in-process above); slow: a process each.
    pytest.param('[[flood.sources]]\nkind = "point"\nhydrograph_m3ps = [-2.0]', "flood.sources[0].hydrograph_m3ps",
                 marks=pytest.mark.slow),
    pytest.param('[[flood.sources]]\nkind = "pipe"', "flood.sources[0].kind", marks=pytest.mark.slow),
])
def test_bad_parameters_exit_2_naming_the_field(tmp_path: Path, flood_lines: str, field: str) -> None:
    """A DEM that does not load, a negative rate, an unknown source kind: one line naming the field, exit 2, before
    any solver run."""
    (tmp_path / "dem.png").write_bytes(b"not an image")
    scenario = tmp_path / "bad.toml"
    scenario.write_text('name = "bad"\n[flood]\nmodel = "hydro"\n' + flood_lines
                        + '\n[fleet]\nlaunch_en_m = [30.0, 0.0]\n')
    done = subprocess.run([sys.executable, "-m", "gcs.plan", str(scenario), "--out", str(tmp_path / "o")],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and field in done.stderr


@pytest.mark.slow
@pytest.mark.parametrize("name", ["breach", "river", "pluvial"])
def test_the_shipped_hydro_scenarios_build_grow_and_are_cageable(name: str) -> None:
    """Each shipped scenario's flood: water at the start, growing, the launch pads outside it."""
    from gcs.scenario import load_scenario

    scenario = load_scenario(name)
    flood = flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
    assert isinstance(flood, HydroFlood)
    assert 0.0 < flood.area_m2(0.0) < flood.area_m2(scenario.duration_s) <= flood.wet_area_m2(scenario.duration_s)
    pads = np.array([v.pad_enu_m[:2] for v in scenario.vehicles])
    assert not flood.is_water(pads, 0.0).any()
