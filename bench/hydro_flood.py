"""What a hydrodynamic flood costs: the ANUGA run per hydro scenario (computed into an empty cache), loading it back
from the cache file in a fresh process's way (memory copy dropped), and answering the world's questions.

``.venv/bin/python bench/hydro_flood.py [--scenarios breach,river,pluvial] [--cache-dir DIR]``

Prints one table row per scenario: mesh triangles, hydraulic seconds simulated, ANUGA CPU [s] (the solver's process
time, measured inside the run), cache file size, cache load wall [ms] (median of 5), and ``is_water`` on a 144x144
camera grid [µs] (median of 200). The cache directory defaults to a fresh temporary one, so every run is computed.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from gcs.scenario import load_scenario
from mock_autopilot.world import hydro_cache
from mock_autopilot.world.config import flood_model_from_config
from mock_autopilot.world.hydro import HydroFlood


def bench(name: str) -> str:
    scenario = load_scenario(name)
    flood = flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
    assert isinstance(flood, HydroFlood)
    run = flood.run
    files = sorted(Path(os.environ[hydro_cache.CACHE_ENV]).glob("*.npz"), key=lambda p: p.stat().st_mtime)
    loads = []
    for _ in range(5):
        hydro_cache.forget_memory()
        t0 = time.perf_counter()
        flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
        loads.append(time.perf_counter() - t0)
    ring = flood.boundary_en_m(30.0)
    points = ring[0] + np.stack(np.meshgrid(np.linspace(-6, 6, 144), np.linspace(-6, 6, 144)), axis=-1)
    queries = []
    for i in range(200):
        t0 = time.perf_counter()
        flood.is_water(points, 30.0 + i * 0.01)
        queries.append(time.perf_counter() - t0)
    cells = run.depth_m.shape[1]
    return (f"| {name} | {4 * cells * cells:,} | {run.times_s[-1]:.0f} | {run.compute_cpu_s:.1f} | "
            f"{files[-1].stat().st_size / 1e6:.1f} MB | {statistics.median(loads) * 1e3:.0f} | "
            f"{statistics.median(queries) * 1e6:.0f} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenarios", default="breach,river,pluvial")
    parser.add_argument("--cache-dir", type=Path, default=None)
    args = parser.parse_args()
    folder = args.cache_dir or Path(tempfile.mkdtemp(prefix="hydro-bench-"))
    os.environ[hydro_cache.CACHE_ENV] = str(folder)
    print("| scenario | triangles | hydraulic s | ANUGA CPU [s] | cache file | cache load [ms] | is_water 144² [µs] |")
    print("|---|---|---|---|---|---|---|")
    for name in args.scenarios.split(","):
        print(bench(name), flush=True)


if __name__ == "__main__":
    main()
