"""``python -m gcs.mission SCENARIO --engine lockstep``: run, then write the same outputs as the full mission."""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from comms.radio_model import radio_model_of
from gcs.lockstep.backend_choice import BackendKind
from gcs.lockstep.engine import LockstepResult, run_lockstep
from gcs.mission.options import MissionOptions
from gcs.report import write_mission_outputs
from gcs.scenario import Scenario, ScenarioError
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.world.config import flood_model_from_config

EXIT_OK = 0
EXIT_CONFIG = 2
EVENTS_NAME = "events.log"

SUMMARY_KEYS = (
    "encircle_time_s", "tracking_rms_last_10s_m", "spacing_cv_final", "max_gap_ratio_final", "polygon_iou_final",
    "coverage_final", "leader_centring_error_last_10s_mean_m", "min_pairwise_distance_m", "near_miss_pairs",
)


def check_models(scenario: Scenario) -> None:
    """Build the flood, camera and radio once so that a bad value fails before the run (ScenarioError)."""
    try:
        flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
        CameraModel(scenario.camera.width_px, scenario.camera.height_px, scenario.camera.fov_deg)
        radio_model_of(scenario.radio, scenario.seed)
    except ValueError as exc:
        raise ScenarioError(str(exc)) from None


def summary_of(metrics: dict[str, Any]) -> dict[str, Any]:
    """The headline figures of a metrics.json (the SPEC §5 targets)."""
    summary = metrics.get("summary", metrics)
    return {key: summary.get(key) for key in SUMMARY_KEYS}


def run_and_write(scenario: Scenario, options: MissionOptions) -> tuple[LockstepResult, dict[str, Any]]:
    """Run the lockstep engine and write every output into ``options.out_dir``; returns the result and metrics."""
    check_models(scenario)
    result = run_lockstep(scenario, options.mode, backend=BackendKind(options.backend))
    options.out_dir.mkdir(parents=True, exist_ok=True)
    paths = write_mission_outputs(result.record, result.flood, scenario.name, scenario.home, options.out_dir,
                                  scenario.camera.fov_deg)
    write_events_log(result.record.events, options.out_dir / EVENTS_NAME)
    metrics = json.loads(paths["metrics"].read_text(encoding="utf-8"))
    return result, metrics


def write_events_log(events: Sequence[tuple[float, str]], path: Path) -> None:
    """The run's events, one line each at its mission time, as the processes engine's events.log has them (without
    its wall-clock column: a lockstep run keeps no wall clock)."""
    path.write_text("".join(f"t={t_s:7.2f}s {text}\n" for t_s, text in events), encoding="utf-8")


def run_mission(scenario: Scenario, options: MissionOptions) -> int:
    """CLI entry of the lockstep engine: exit 0 when the run reached its end and the outputs are written."""
    result, metrics = run_and_write(scenario, options)
    sim_s = result.steps / scenario.control_rate_hz
    print(f"lockstep {scenario.name} mode={options.mode} backend={options.backend} seed={scenario.seed}: "
          f"{sim_s:.0f} s simulated in {result.wall_s:.1f} s wall ({sim_s / max(result.wall_s, 1e-9):.1f}x real time), {result.frames} camera frames")
    for key, value in summary_of(metrics).items():
        print(f"  {key}: {value}")
    print(f"outputs: {options.out_dir}")
    sys.stdout.flush()
    return EXIT_OK
