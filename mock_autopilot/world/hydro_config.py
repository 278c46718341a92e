"""``model = "hydro"``: a ``[flood]`` table made into a cached shallow-water run (see :mod:`hydro`).

Keys (lengths in metres; times in *hydraulic* seconds unless said otherwise):

- ground: ``landform = "farmland" | "valley" | "basin"`` with :class:`LandformSpec`'s sizes (``terrain_size_m``,
  ``cell_m``, ``relief_m``, ``slope``, ``slope_toward_deg``, ``hedges``, ``hedge_height_m``, ``ditches``,
  ``ditch_depth_m``, ``channel_width_m``, ``channel_depth_m``, ``meander_amplitude_m``, ``meander_wavelength_m``,
  ``depressions``, ``depression_depth_m``, ``depression_radius_m``) and ``terrain_seed`` (default the scenario seed),
  or a DEM (``dem_path`` and the ``dem_*`` keys of the terrain model).
- solver: ``mesh_cell_m`` (1.5), ``manning_n`` (0.04), ``boundary`` ("reflective" or "outflow", or a table of
  ``north``/``south``/``east``/``west``), ``run_s`` (hydraulic time simulated), ``frame_interval_s`` (2).
- water in: ``[[flood.sources]]`` with ``kind = "point" | "line"``, ``at_en_m = [e, n]`` (point) or
  ``line_en_m = [[e, n], [e, n]]`` (line), ``radius_m`` (disc radius, or half the strip's width), and the
  hydrograph ``hydrograph_t_s`` / ``hydrograph_m3ps``; rain ``rain_mm_per_h`` until ``rain_until_s``.
- replay: ``start_s`` (hydraulic time at flood time 0), ``time_scale`` (hydraulic s per flood-clock s, 1),
  ``wet_depth_m`` (0.02).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from mock_autopilot.world.flood_fields import FloodConfigError, Fields, dem_heightmap
from mock_autopilot.world.hydro import HydroFlood
from mock_autopilot.world.hydro_cache import cached_run, run_key
from mock_autopilot.world.hydro_solver import run_anuga, solver_version
from mock_autopilot.world.hydro_spec import SIDES, BoundaryKind, Hydrograph, HydroSpec, Source, SourceKind
from mock_autopilot.world.landforms import Landform, LandformSpec, landform_heightmap

MAX_MESH_CELLS = 200
"""Largest mesh side [cells] (4·200² = 160,000 triangles)."""


def _landform(f: Fields, seed: int) -> LandformSpec:
    name = f.text("landform", "farmland")
    names = [lf.value for lf in Landform]
    if name not in names:
        raise FloodConfigError(f"{f.name('landform')}: unknown landform {name!r}; expected one of {', '.join(names)}")
    values: dict[str, Any] = {"landform": Landform(name)}
    for item in dataclasses.fields(LandformSpec):
        if item.name == "landform":
            continue
        key = "terrain_size_m" if item.name == "size_m" else item.name
        if item.type == "int":
            count = f.integer(key, item.default)
            if count < 0:
                raise FloodConfigError(f"{f.name(key)}: must be >= 0, got {count}")
            values[item.name] = count
        else:
            positive = item.name not in ("slope_toward_deg", "slope", "relief_m")
            values[item.name] = f.number(key, item.default, positive=positive, non_negative=not positive
                                         and item.name != "slope_toward_deg")
    return LandformSpec(**values)


def _source(raw: Any, prefix: str, f: Fields) -> Source:
    if not isinstance(raw, Mapping):
        raise FloodConfigError(f"{prefix}: must be a table, got {raw!r}")
    s = Fields(raw, f.base_dir, prefix)
    s.used.discard("model")
    kind_name = s.text("kind", None)
    kinds = [k.value for k in SourceKind]
    if kind_name not in kinds:
        raise FloodConfigError(f"{s.name('kind')}: unknown source kind {kind_name!r}; expected one of {', '.join(kinds)}")
    kind = SourceKind(kind_name)
    if kind is SourceKind.POINT:
        points: tuple[tuple[float, float], ...] = (s.pair("at_en_m", (0.0, 0.0)),)
    else:
        s.used.add("line_en_m")
        line = raw.get("line_en_m")
        if not isinstance(line, (list, tuple)) or len(line) != 2:
            raise FloodConfigError(f"{s.name('line_en_m')}: must be two points [[e, n], [e, n]], got {line!r}")
        ends = Fields({"a": line[0], "b": line[1]}, f.base_dir, s.name("line_en_m"))
        points = (ends.pair("a", (0.0, 0.0)), ends.pair("b", (0.0, 0.0)))
    t = s.numbers("hydrograph_t_s", (0.0,))
    q = s.numbers("hydrograph_m3ps", (1.0,), non_negative=True)
    if len(t) != len(q):
        raise FloodConfigError(f"{s.name('hydrograph_m3ps')}: {len(q)} rates for {len(t)} times in hydrograph_t_s")
    if any(b <= a for a, b in zip(t, t[1:])):
        raise FloodConfigError(f"{s.name('hydrograph_t_s')}: times must increase, got {list(t)}")
    radius = s.number("radius_m", 3.0, positive=True)
    s.reject_unknown()
    return Source(kind, points, Hydrograph(t, q), radius)


def _boundaries(f: Fields) -> tuple[BoundaryKind, BoundaryKind, BoundaryKind, BoundaryKind]:
    f.used.add("boundary")
    raw = f.table.get("boundary", "reflective")
    kinds = [k.value for k in BoundaryKind]
    table = raw if isinstance(raw, Mapping) else {side: raw for side in SIDES}
    unknown = set(table) - set(SIDES)
    if unknown:
        raise FloodConfigError(f"{f.name('boundary')}: unknown side {sorted(unknown)[0]!r}; sides are {', '.join(SIDES)}")
    out = []
    for side in SIDES:
        value = table.get(side, "reflective")
        if value not in kinds:
            name = f.name("boundary") + (f".{side}" if isinstance(raw, Mapping) else "")
            raise FloodConfigError(f"{name}: unknown boundary {value!r}; expected one of {', '.join(kinds)}")
        out.append(BoundaryKind(value))
    return out[0], out[1], out[2], out[3]


def hydro_flood(f: Fields, seed: int) -> HydroFlood:
    """The hydro flood a ``[flood]`` table describes: ground, run (from the cache or computed), replay settings."""
    heightmap = dem_heightmap(f, (0.0, 0.0))
    if heightmap is None:
        heightmap = landform_heightmap(_landform(f, seed), f.integer("terrain_seed", seed))
    mesh_cell = f.number("mesh_cell_m", 1.5, positive=True)
    side_m = min(heightmap.shape) * heightmap.cell_m
    if not 4 <= side_m / mesh_cell <= MAX_MESH_CELLS:
        raise FloodConfigError(f"{f.name('mesh_cell_m')}: {side_m:g} m / {mesh_cell:g} m = {side_m / mesh_cell:.0f} "
                               f"cells a side; must be 4 .. {MAX_MESH_CELLS}")
    f.used.add("sources")
    raw_sources = f.table.get("sources", [])
    if not isinstance(raw_sources, list):
        raise FloodConfigError(f"{f.name('sources')}: must be an array of tables ([[flood.sources]])")
    sources = tuple(_source(raw, f"{f.name('sources')}[{i}]", f) for i, raw in enumerate(raw_sources))
    run_s = f.number("run_s", 120.0, positive=True)
    rain = f.number("rain_mm_per_h", 0.0, non_negative=True)
    if not sources and rain == 0.0:
        raise FloodConfigError(f"{f.name('sources')}: no sources and no rain_mm_per_h; the flood would stay dry")
    spec = HydroSpec(
        mesh_cell_m=mesh_cell, manning_n=f.number("manning_n", 0.04, positive=True), sources=sources,
        rain_mm_per_h=rain, rain_until_s=f.number("rain_until_s", run_s, non_negative=True),
        boundaries=_boundaries(f), end_s=run_s,
        frame_interval_s=f.number("frame_interval_s", 2.0, positive=True),
    )
    if spec.frame_interval_s * 2 > run_s:
        raise FloodConfigError(f"{f.name('frame_interval_s')}: must be at most half of run_s ({run_s:g}) s")
    for i, source in enumerate(sources):
        if not heightmap.contains(source.points_en_m[0]) or not heightmap.contains(source.points_en_m[-1]):
            raise FloodConfigError(f"{f.name('sources')}[{i}]: {list(source.points_en_m)} lies outside the terrain")
    start_s = f.number("start_s", 0.0, non_negative=True)
    time_scale = f.number("time_scale", 1.0, positive=True)
    wet = f.number("wet_depth_m", 0.02, positive=True)
    f.reject_unknown()
    run, _ = cached_run(run_key(spec, heightmap, solver_version()), lambda: run_anuga(spec, heightmap))
    return HydroFlood(run, sources[0].anchor_en_m if sources else None, wet, time_scale, start_s, spec.manning_n)
