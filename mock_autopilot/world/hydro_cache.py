"""The hydrodynamic run, computed once and replayed: an on-disk cache keyed by a hash of every input.

A run is stored as one ``<key>.npz`` in the cache directory (``FLOODWATCH_CACHE_DIR``, which ``--cache-dir`` sets,
else ``$XDG_CACHE_HOME/floodwatch/hydro`` or ``~/.cache/floodwatch/hydro``). Several processes (the ground station,
the fleet, the cameras, campaign workers) may need the same run at once: the first to take the key's lock file
computes it, writes a temporary file in the same directory and renames it into place (atomic on POSIX), the others
wait on the lock and then read. A file that does not load or does not hold what the key promises is recomputed,
never trusted. Within a process, runs are kept in memory by key.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import tempfile
import zipfile
from collections.abc import Callable
from dataclasses import asdict
from enum import Enum
from pathlib import Path
from typing import Any

import numpy as np

from mock_autopilot.world.heightmap import Heightmap
from mock_autopilot.world.hydro_solver import HydroRun
from mock_autopilot.world.hydro_spec import HydroSpec

CACHE_ENV = "FLOODWATCH_CACHE_DIR"
FORMAT_VERSION = 1
"""Bumped whenever the solver set-up or the stored layout changes, so old files are not reused."""
_ARRAYS = ("times_s", "depth_m", "ground_m", "volume_grid_m3", "volume_out_m3", "volume_added_m3")
_memory: dict[str, HydroRun] = {}


def default_cache_dir() -> Path:
    """Where runs are cached: ``$FLOODWATCH_CACHE_DIR``, else the user's cache directory."""
    explicit = os.environ.get(CACHE_ENV)
    if explicit:
        return Path(explicit)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "floodwatch" / "hydro"


def _plain(value: Any) -> Any:
    if isinstance(value, Enum):
        return value.value
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def run_key(spec: HydroSpec, heightmap: Heightmap, solver_version: str) -> str:
    """SHA-256 over the spec, the ground (bytes, cell, centre), the solver's version and the file format."""
    digest = hashlib.sha256()
    header = {"spec": _plain(asdict(spec)), "cell_m": heightmap.cell_m, "center": list(heightmap.center_en_m),
              "shape": list(heightmap.shape), "solver": solver_version, "format": FORMAT_VERSION}
    digest.update(json.dumps(header, sort_keys=True).encode())
    digest.update(np.ascontiguousarray(heightmap.heights_m, dtype=np.float32).tobytes())
    return digest.hexdigest()[:32]


def _load(path: Path, key: str) -> HydroRun | None:
    """The run stored at ``path`` if it is complete and consistent, else None."""
    try:
        with np.load(path, allow_pickle=False) as data:
            if str(data["key"]) != key:
                return None
            arrays = {name: np.array(data[name]) for name in _ARRAYS}
            cell_m = float(data["cell_m"])
            center = tuple(float(v) for v in data["center_en_m"])
            cpu_s = float(data["compute_cpu_s"])
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):
        return None
    frames = arrays["depth_m"]
    f = len(arrays["times_s"])
    if frames.ndim != 3 or frames.shape[0] != f or f < 2 or frames.shape[1:] != arrays["ground_m"].shape:
        return None
    if not all(np.all(np.isfinite(a)) for a in arrays.values()):
        return None
    return HydroRun(cell_m=cell_m, center_en_m=(center[0], center[1]), compute_cpu_s=cpu_s, **arrays)


def _store(path: Path, key: str, run: HydroRun) -> None:
    """Write to a temporary file beside ``path`` and rename it into place (readers never see half a file)."""
    fd, tmp = tempfile.mkstemp(prefix=path.stem + ".", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as handle:
            np.savez(handle, key=np.array(key), cell_m=np.array(run.cell_m), center_en_m=np.array(run.center_en_m),
                     compute_cpu_s=np.array(run.compute_cpu_s), **{name: getattr(run, name) for name in _ARRAYS})
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def cached_run(key: str, compute: Callable[[], HydroRun], directory: Path | None = None) -> tuple[HydroRun, bool]:
    """(run, computed here) for ``key``: from memory, from the cache file, or computed under the key's lock."""
    if key in _memory:
        return _memory[key], False
    folder = directory if directory is not None else default_cache_dir()
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{key}.npz"
    run = _load(path, key) if path.exists() else None
    computed = False
    if run is None:
        with open(folder / f"{key}.lock", "a+b") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            try:
                run = _load(path, key) if path.exists() else None
                if run is None:
                    run = compute()
                    _store(path, key, run)
                    computed = True
            finally:
                fcntl.flock(lock, fcntl.LOCK_UN)
    _memory[key] = run
    return run, computed


def forget_memory() -> None:
    """Drop the in-process copies (tests that exercise the file cache)."""
    _memory.clear()
