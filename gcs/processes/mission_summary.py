"""The end of a mission run: the engine verdict, the outputs written from the record, the safety verdict folded
into metrics.json, and the summary lines the operator reads."""

from __future__ import annotations

import datetime as dt
import json
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from rich.console import Console

from gcs.processes.agent_exit_report import agent_refused_copies
from gcs.processes.recorder import MissionRecorder
from gcs.processes.run_verdict import EngineVerdict, safety_verdict
from gcs.relay_refusals import refused_copies_line
from gcs.report import write_mission_outputs
from gcs.report.outputs import write_metrics_json
from gcs.scenario import Scenario
from mock_autopilot.world.flood_model import FloodModel

if TYPE_CHECKING:
    from gcs.processes.ground_radio import GroundRadio
    from gcs.processes.mission_children import MissionChildren


def write_outputs(recorder: MissionRecorder, flood: FloodModel | None, scenario: Scenario, out_dir: Path,
                  start_utc: dt.datetime | None, console: Console, engine: EngineVerdict) -> bool:
    """Save the record and write the report (metrics, GeoJSON/KML, plots); False when there is nothing to report
    (no flight recorded, or no flood model to measure it against) or the report failed."""
    if len(recorder):
        recorder.save_snapshot(out_dir / "record.npz")
    if len(recorder) < 2 or flood is None:
        console.print(f"no flight recorded ({engine.text()}); events and logs are in {out_dir}")
        return False
    try:
        write_mission_outputs(recorder.record(), flood, scenario.name, scenario.home, out_dir, scenario.camera.fov_deg,
                              start_utc=start_utc)
    except Exception as exc:  # noqa: BLE001 - the report must not hide the mission's own exit code
        console.print(f"[red]writing the report failed:[/] {exc}")
        print(f"gcs.processes: writing the report failed: {exc!r}", file=sys.stderr)
        return False
    return True


def note_refused_copies(recorder: MissionRecorder, children: MissionChildren | None, radio: GroundRadio | None,
                        events: Callable[[str], None]) -> None:
    """Put the relayed copies refused as impossible in the record and events.log: each agent's count from its
    exit report (only the agents this station started and stopped; the others' stay unknown), and the ground
    station's radio node's (None: outside the radio)."""
    logs = {} if children is None else {vid: child.log_path for vid, child in children.agents.items()}
    per_vehicle = [agent_refused_copies(logs[vid], vid) if vid in logs else None for vid in recorder.vehicle_ids]
    ground = None if radio is None else radio.node.refused_copies
    recorder.refused_copies, recorder.ground_refused_copies = per_vehicle, ground
    events(refused_copies_line(recorder.vehicle_ids, per_vehicle, ground))


def print_summary(out_dir: Path, complete: bool, engine: EngineVerdict, failsafes: Sequence[str],
                  events: Callable[[str], None], console: Console) -> None:
    """Fold the safety verdict and the engine health into metrics.json and print the headline figures."""
    metrics_path = out_dir / "metrics.json"
    if not metrics_path.exists():
        return
    try:
        metrics = json.loads(metrics_path.read_text())
    except (OSError, ValueError):
        return
    summary = metrics.get("summary", metrics)
    safety = safety_verdict(summary, list(failsafes))
    events(safety.text())
    metrics["engine_health"] = engine.as_json()
    metrics["safety"] = safety.as_json()
    write_metrics_json(metrics, metrics_path)
    keys = [k for k in ("encircle_time_s", "polygon_iou_final", "coverage_final", "spacing_cv_final",
                        "tracking_rms_last_10s_m", "min_pairwise_distance_m", "near_miss_pairs") if k in summary]
    shown = ", ".join(f"{k}={summary[k]:.3f}" if isinstance(summary[k], float) else f"{k}={summary[k]}" for k in keys)
    console.print(f"metrics: {shown}; outputs in {out_dir}")
    for loss in metrics.get("losses", []):
        recovery = loss.get("recovery_time_s")
        recovered = f"spacing CV back under 0.1 after {recovery:.1f} s" if isinstance(recovery, float) else "no recovery"
        console.print(f"  vehicle {loss['vehicle_id']} ({loss['role']}) lost at flood time {loss['t_s']:.1f} s: "
                      f"{recovered}")
    console.print(f"mission {'complete' if complete else 'INCOMPLETE'} | {engine.text()} | {safety.text()}")
