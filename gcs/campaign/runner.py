"""One campaign run inside a worker: resolve the scenario, fly it in lockstep, score it, return one flat row.

Everything the row holds is a scalar (every summary metric of ``gcs.metrics.compute_mission_metrics``, the run's
parameters, wall and CPU time), so rows from many runs stack into one Parquet table. A run that raises still
returns a row, with the error, so the campaign records it and goes on; only a dying worker process leaves no row,
and dask then runs it again elsewhere.
"""

from __future__ import annotations

import json
import os
import socket
import time
import traceback
from pathlib import Path
from typing import Any

from gcs.campaign.grid import RunSpec

Row = dict[str, Any]

ERROR_COLUMN = "error"
GRID_PREFIX = "grid:"
"""Column name prefix of a grid key's value (``grid:radio.loss``), kept as the text given on the command line."""


def _scalar(value: Any) -> Any:
    """A Parquet-friendly cell: numbers, text, booleans and None as they are, anything else as JSON text."""
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        return value
    return json.dumps(value)


def base_row(spec: RunSpec, code_version: str) -> Row:
    """The columns every row has, failed or not: the run's identity and parameters."""
    row: Row = {
        "run_id": spec.run_id,
        "scenario": spec.scenario,
        "mode": spec.mode.value,
        "seed": spec.seed,
        "cell": spec.cell_label(),
        "overrides": " ".join(spec.fixed),
        "code_version": code_version,
        ERROR_COLUMN: None,
    }
    row.update({f"{GRID_PREFIX}{key}": value for key, value in spec.cell})
    return row


def run_one(spec: RunSpec, code_version: str, outputs_dir: str | None = None) -> Row:
    """Fly one run and return its row; with ``outputs_dir`` also write the mission's files there.

    Imports live inside so that a dask worker unpickles this function cheaply and sets OpenCV to one thread before
    any frame is rendered (its thread pool costs about a third more CPU when runs are already in parallel).
    """
    import cv2

    cv2.setNumThreads(1)
    row = base_row(spec, code_version)
    row["worker"] = f"{socket.gethostname()}:{os.getpid()}"
    wall_start = time.perf_counter()
    cpu_start = time.process_time()
    try:
        row.update(_fly(spec, outputs_dir))
    except Exception as exc:  # noqa: BLE001 - any failure of a run is its result, recorded in the row
        last = traceback.extract_tb(exc.__traceback__)[-1:]
        where = f" at {Path(last[0].filename).name}:{last[0].lineno}" if last else ""
        row[ERROR_COLUMN] = f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}{where}"
    row["wall_s"] = time.perf_counter() - wall_start
    row["cpu_s"] = time.process_time() - cpu_start
    return row


def _fly(spec: RunSpec, outputs_dir: str | None) -> Row:
    from gcs.lockstep.engine import run_lockstep
    from gcs.lockstep.run import check_models
    from gcs.metrics.mission import compute_mission_metrics
    from gcs.scenario import load_scenario

    scenario = load_scenario(spec.scenario, spec.overrides())
    check_models(scenario)
    result = run_lockstep(scenario, spec.mode.value)
    if outputs_dir is not None:
        from gcs.report import write_mission_outputs

        out = Path(outputs_dir)
        out.mkdir(parents=True, exist_ok=True)
        paths = write_mission_outputs(result.record, result.flood, scenario.name, scenario.home, out,
                                      scenario.camera.fov_deg)
        metrics = json.loads(paths["metrics"].read_text(encoding="utf-8"))
    else:
        metrics = compute_mission_metrics(result.record, result.flood, scenario.camera.fov_deg)
    row: Row = {key: _scalar(value) for key, value in metrics["summary"].items()}
    sim_s = result.steps / scenario.control_rate_hz
    row.update(
        scenario_name=scenario.name, vehicles=len(scenario.vehicles), sim_s=sim_s, steps=result.steps,
        frames=result.frames, radio_heard=result.radio_heard, radio_lost=result.radio_lost,
        engine_wall_s=result.wall_s, engine_cpu_s=result.cpu_s,
    )
    return row
