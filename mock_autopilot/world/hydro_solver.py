"""Run ANUGA (the shallow-water solver of Geoscience Australia and the ANU) for a :class:`HydroSpec` over a heightmap.

The domain is the heightmap's square, meshed as ``rectangular_cross_domain`` (every ``mesh_cell_m`` square cut into
four triangles by its diagonals), Manning friction, sources as ``Rate_operator`` inflows (a disc around a point, a
thin strip along a line: the operator spreads Q over the region's area, so the volume put in is exact), rain as a
domain-wide rate, and reflective or transmissive (outflow) edges. Every ``frame_interval_s`` of hydraulic time the
depth of the four triangles of each square is averaged into one raster cell (equal areas, so the raster holds the
same volume as the mesh). This is the only module that imports ``anuga``; everything downstream reads rasters.
"""

from __future__ import annotations

import contextlib
import importlib.metadata
import io
import logging
import time
import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from mock_autopilot.world.heightmap import Heightmap
from mock_autopilot.world.hydro_spec import SIDES, BoundaryKind, HydroSpec, Source, SourceKind

MAX_TIMESTEP_S = 0.25
"""Longest solver step [s]: operators apply Q at the start of each step, so a dry domain's long steps would put in
too little water while a hydrograph rises; 0.25 s keeps that error well under 1 % (wet steps are shorter anyway)."""
_ANUGA_TAGS = {"north": "top", "south": "bottom", "east": "right", "west": "left"}


@dataclass(frozen=True, eq=False)
class HydroRun:
    """Depth rasters of one run (north-up, row 0 north, like :class:`Heightmap`) and its water balance."""

    times_s: NDArray[np.float64]
    """(F,) hydraulic times of the frames [s]."""
    depth_m: NDArray[np.float32]
    """(F, rows, cols) water depth per raster cell [m]."""
    ground_m: NDArray[np.float32]
    """(rows, cols) mesh ground height per raster cell [m] (the mean over the cell's four triangles)."""
    cell_m: float
    center_en_m: tuple[float, float]
    volume_grid_m3: NDArray[np.float64]
    """(F,) water on the mesh [m³]."""
    volume_out_m3: NDArray[np.float64]
    """(F,) water that has left through outflow edges [m³]."""
    volume_added_m3: NDArray[np.float64]
    """(F,) water the operators report adding [m³]."""
    compute_cpu_s: float


def solver_version() -> str:
    """The installed ANUGA's version (part of the cache key), read without importing it."""
    return importlib.metadata.version("anuga")


def _mesh_size(heightmap: Heightmap, cell_m: float) -> tuple[int, float, float, float]:
    """(cells a side, mesh cell [m], west edge, south edge) of the square mesh over the heightmap."""
    rows, cols = heightmap.shape
    side_m = min(rows, cols) * heightmap.cell_m
    n = max(int(side_m // cell_m), 4)
    mesh_cell = side_m / n
    west = heightmap.center_en_m[0] - side_m / 2.0
    south = heightmap.center_en_m[1] - side_m / 2.0
    return n, mesh_cell, west, south


def _add_source(anuga: object, domain: object, source: Source, west: float, south: float) -> None:
    pts = np.asarray(source.points_en_m, float) - (west, south)
    q = source.hydrograph.rate_m3ps
    if source.kind is SourceKind.POINT:
        anuga.Rate_operator.inflow(domain, rate=q, center=(float(pts[0, 0]), float(pts[0, 1])),
                                   radius=source.radius_m)
        return
    a, b = pts[0], pts[1]
    along = (b - a) / max(float(np.hypot(*(b - a))), 1e-9)
    normal = np.array([-along[1], along[0]]) * source.radius_m
    strip = [a + normal, b + normal, b - normal, a - normal]
    anuga.Rate_operator.inflow(domain, rate=q, polygon=[[float(p[0]), float(p[1])] for p in strip])


def run_anuga(spec: HydroSpec, heightmap: Heightmap) -> HydroRun:
    """Evolve the domain to ``spec.end_s`` and return the depth rasters (deterministic: serial ANUGA, fixed inputs)."""
    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        # ANUGA announces on stdout that it runs without MPI (serial is what we want); keep our stdout clean.
        warnings.simplefilter("ignore")
        logging.getLogger("anuga").setLevel(logging.ERROR)
        import anuga
    cpu0 = time.process_time()
    n, cell, west, south = _mesh_size(heightmap, spec.mesh_cell_m)
    domain = anuga.rectangular_cross_domain(n, n, len1=n * cell, len2=n * cell)
    domain.set_store(False)
    domain.set_evolve_max_timestep(MAX_TIMESTEP_S)
    domain.set_quantity("elevation", lambda x, y: heightmap.height_at(np.stack([x + west, y + south], axis=-1)),
                        location="centroids")
    domain.set_quantity("friction", spec.manning_n, location="centroids")
    domain.set_quantity("stage", expression="elevation", location="centroids")
    walls = {
        BoundaryKind.REFLECTIVE: anuga.Reflective_boundary(domain),
        BoundaryKind.OUTFLOW: anuga.Transmissive_boundary(domain),
    }
    domain.set_boundary({_ANUGA_TAGS[side]: walls[kind] for side, kind in zip(SIDES, spec.boundaries)})
    for source in spec.sources:
        _add_source(anuga, domain, source, west, south)
    if spec.rain_mm_per_h > 0.0:
        rain, until = spec.rain_mm_per_h, spec.rain_until_s
        anuga.Rate_operator.rainfall(domain, rate=lambda t: rain if t < until else 0.0)

    centroids = np.asarray(domain.centroid_coordinates)
    col = np.clip((centroids[:, 0] // cell).astype(int), 0, n - 1)
    row = n - 1 - np.clip((centroids[:, 1] // cell).astype(int), 0, n - 1)
    flat = row * n + col
    counts = np.bincount(flat, minlength=n * n).astype(float)

    def raster(values: NDArray[np.float64]) -> NDArray[np.float32]:
        return (np.bincount(flat, weights=values, minlength=n * n) / counts).reshape(n, n).astype(np.float32)

    stage = domain.quantities["stage"].centroid_values
    elevation = domain.quantities["elevation"].centroid_values
    times, frames, grid, out, added = [], [], [], [], []
    for _ in domain.evolve(yieldstep=spec.frame_interval_s, finaltime=spec.end_s):
        times.append(float(domain.get_time()))
        frames.append(raster(np.maximum(stage - elevation, 0.0)))
        grid.append(float(domain.get_water_volume()))
        out.append(-float(domain.get_boundary_flux_integral()))
        added.append(float(domain.get_fractional_step_volume_integral()))
    return HydroRun(
        times_s=np.asarray(times), depth_m=np.stack(frames), ground_m=raster(elevation),
        cell_m=cell, center_en_m=(west + n * cell / 2.0, south + n * cell / 2.0),
        volume_grid_m3=np.asarray(grid), volume_out_m3=np.asarray(out), volume_added_m3=np.asarray(added),
        compute_cpu_s=time.process_time() - cpu0,
    )
