"""``python -m gcs.results_table``: run every scenario in both modes with the lockstep engine and write docs/RESULTS.md.

Every figure in the file comes from a real run made by this script (metrics from ground truth by
``gcs.metrics.compute_mission_metrics``). Three tables:

1. the issue's targets on ``circle``, seeds 1-5, paper and improved mode (mean, worst);
2. one row per scenario and mode (the scenario's own seed);
3. the ṗ feed-forward readings of eq 5 on ``circle`` (SPEC §2: "measure both").
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from gcs.lockstep.engine import run_lockstep
from gcs.metrics.mission import compute_mission_metrics
from gcs.scenario import Scenario, load_scenario, scenario_names

Row = dict[str, Any]

COLUMNS: tuple[tuple[str, str, str], ...] = (
    ("encircle_time_s", "T_enc [s]", "{:.1f}"),
    ("tracking_rms_last_10s_m", "track RMS last 10 s [m]", "{:.2f}"),
    ("spacing_cv_final", "spacing CV", "{:.3f}"),
    ("max_gap_ratio_final", "max gap/ideal", "{:.2f}"),
    ("polygon_iou_final", "polygon IoU", "{:.3f}"),
    ("polygon_hausdorff_final_m", "Hausdorff [m]", "{:.2f}"),
    ("coverage_final", "coverage", "{:.3f}"),
    ("leader_centring_error_last_10s_mean_m", "leader err [m]", "{:.2f}"),
    ("min_pairwise_distance_m", "min pair [m]", "{:.2f}"),
    ("near_miss_pairs", "pairs < 1 m", "{:d}"),
)

TARGETS: tuple[tuple[str, str, float], ...] = (
    ("encircle_time_s", "<=", 20.0),
    ("spacing_cv_final", "<=", 0.05),
    ("max_gap_ratio_final", "<=", 1.15),
    ("tracking_rms_last_10s_m", "<=", 0.5),
    ("polygon_iou_final", ">=", 0.97),
    ("coverage_final", ">=", 0.97),
    ("leader_centring_error_last_10s_mean_m", "<=", 1.0),
    ("min_pairwise_distance_m", ">=", 1.0),
)


def run_row(scenario: Scenario, mode: str, seed: int | None = None, label: str | None = None, **param_changes: Any) -> Row:
    """One lockstep run and its headline metrics."""
    params = replace(scenario.control_params(mode), **param_changes) if param_changes else None
    result = run_lockstep(scenario, mode, seed=seed, control_params=params)
    metrics = compute_mission_metrics(result.record, result.flood, scenario.camera.fov_deg)
    summary = metrics.get("summary", metrics)
    row: Row = {key: summary.get(key) for key, _, _ in COLUMNS}
    row.update(scenario=scenario.name, mode=mode, seed=result.record.seed, label=label or mode,
               vehicles=len(scenario.vehicles), wall_s=result.wall_s, sim_s=result.steps / scenario.control_rate_hz)
    return row


def _fmt(value: Any, pattern: str) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "—"
    if pattern == "{:d}":
        return str(int(value))
    return pattern.format(float(value))


def _table(rows: Sequence[Row], lead: Sequence[tuple[str, str]]) -> list[str]:
    header = [title for _, title in lead] + [title for _, title, _ in COLUMNS]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for row in rows:
        cells = [str(row[key]) for key, _ in lead]
        if "error" in row:
            cells += [f"not run: {row['error']}"] + [""] * (len(COLUMNS) - 1)
        else:
            cells += [_fmt(row.get(key), pattern) for key, _, pattern in COLUMNS]
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def _passes(value: Any, op: str, limit: float) -> bool:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return False
    return float(value) <= limit if op == "<=" else float(value) >= limit


def _targets_table(seed_rows: Sequence[Row]) -> list[str]:
    lines = ["| metric | target | paper mean | paper worst | improved mean | improved worst | improved meets target (all seeds) |",
             "|---|---|---|---|---|---|---|"]
    pattern = {key: p for key, _, p in COLUMNS}
    title = {key: t for key, t, _ in COLUMNS}
    for key, op, limit in TARGETS:
        cells = [title[key], f"{op} {limit:g}"]
        ok = "—"
        for mode in ("paper", "improved"):
            values = [r.get(key) for r in seed_rows if r["mode"] == mode]
            finite = [float(v) for v in values if v is not None and not (isinstance(v, float) and math.isnan(v))]
            mean = sum(finite) / len(finite) if finite else None
            worst = (max(finite) if op == "<=" else min(finite)) if len(finite) == len(values) and finite else None
            cells += [_fmt(mean, pattern[key]), _fmt(worst, pattern[key])]
            if mode == "improved":
                ok = "yes" if values and all(_passes(v, op, limit) for v in values) else "no"
        cells.append(ok)
        lines.append("| " + " | ".join(cells) + " |")
    return lines


@dataclass(frozen=True)
class Job:
    """One run of the table: which scenario, mode, seed, and parameter changes; ``table`` names its table."""

    table: str
    scenario: str
    mode: str
    seed: int | None = None
    label: str | None = None
    pdot_reading: str | None = None


def run_job(job: Job) -> Row:
    """Run one job (in this process or a worker); a run that cannot start gives a row saying why."""
    changes = {"pdot_reading": job.pdot_reading} if job.pdot_reading is not None else {}
    try:
        row = run_row(load_scenario(job.scenario), job.mode, seed=job.seed, label=job.label, **changes)
    except (ValueError, ImportError) as exc:
        row = {"scenario": job.scenario, "mode": job.mode, "seed": job.seed, "label": job.label or job.mode,
               "vehicles": "—", "wall_s": 0.0, "sim_s": 0.0, "error": str(exc).splitlines()[0]}
    row["table"] = job.table
    return row


def plan_jobs(scenarios: Sequence[str], seeds: Sequence[int]) -> list[Job]:
    """Every run the three tables need (the circle's own-seed scenario row reuses its seed run)."""
    circle_seed = load_scenario("circle").seed
    jobs = [Job("seeds", "circle", mode, seed) for mode in ("paper", "improved") for seed in seeds]
    for name in scenarios:
        if name == "circle" and circle_seed in seeds:
            continue
        jobs += [Job("scenarios", name, mode) for mode in ("paper", "improved")]
    jobs += [Job("pdot", "circle", mode, circle_seed, f"{mode}, ṗ {reading}", reading)
             for mode in ("paper", "improved") for reading in ("full", "none")]
    return jobs


def build_results(scenarios: Sequence[str], seeds: Sequence[int], log: Callable[[str], None], jobs: int = 1) -> dict[str, list[Row]]:
    """Run everything (``jobs`` worker processes); returns the rows of the three tables."""
    plan = plan_jobs(scenarios, seeds)
    rows: list[Row] = []
    if jobs <= 1:
        for job in plan:
            rows.append(run_job(job))
            log(f"{job.scenario} {job.label or job.mode} seed {job.seed}: {rows[-1]['wall_s']:.1f} s wall")
    else:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            for job, row in zip(plan, pool.map(run_job, plan)):
                rows.append(row)
                log(f"{job.scenario} {job.label or job.mode} seed {job.seed}: {row['wall_s']:.1f} s wall")
    results: dict[str, list[Row]] = {"seeds": [], "scenarios": [], "pdot": []}
    for row in rows:
        results[row["table"]].append(row)
    circle_seed = load_scenario("circle").seed
    ordered: list[Row] = []
    for name in scenarios:
        for mode in ("paper", "improved"):
            pool_rows = results["seeds"] if name == "circle" and circle_seed in seeds else results["scenarios"]
            ordered += [r for r in pool_rows if r["scenario"] == name and r["mode"] == mode
                        and (pool_rows is results["scenarios"] or r["seed"] == circle_seed)]
    results["scenarios"] = ordered
    pdot: list[Row] = []
    for mode in ("paper", "improved"):
        normal = [dict(r, label=f"{mode}, ṗ normal") for r in results["seeds"] if r["mode"] == mode and r["seed"] == circle_seed]
        if not normal:
            normal = [run_job(Job("pdot", "circle", mode, circle_seed, f"{mode}, ṗ normal", "normal"))]
        pdot += normal + [r for r in results["pdot"] if r["mode"] == mode]
    results["pdot"] = pdot
    return results


def render_markdown(results: dict[str, list[Row]], seeds: Sequence[int], command: str, wall_s: float) -> str:
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = [
        "# Results",
        "",
        f"Generated by `{command}` on {stamp} ({wall_s:.0f} s wall). Every number below comes from a lockstep run",
        "(`gcs.lockstep`: the agents' onboard core `vehicle_agents.core` for the whole fleet at the scenario's control",
        "rate, the kinematic vehicle backend with PX4's limits, the camera renderer and OpenCV perception at its camera",
        "rate, the comms radio model carrying the state messages in their wire format) scored from ground truth by",
        "`gcs.metrics.compute_mission_metrics`. Do not edit by hand: re-run the script.",
        "",
        "Modes: `paper` = eqs 4-10 and Algorithm 1 as SPEC §2 reads them (u_c = 1 m/s for every boundary drone until",
        "the leading drones meet, β separation with d = 10 m, eq 9 vertex mean, eq 10 targets at the layer fraction,",
        "ṗ fed forward along the edge normal). `improved` = 3 m/s encircling by each group's leading drone only,",
        "equal-gap consensus along the ring, edge-point tracking, area-centroid leader, and a braking-aware collision",
        "barrier between all roles. Columns: see SPEC §5; 'final' values at the last sample, 'last 10 s' averaged.",
        "",
        f"## Targets on `circle`, seeds {', '.join(str(s) for s in seeds)}",
        "",
        *_targets_table(results["seeds"]),
        "",
        "Per seed:",
        "",
        *_table(results["seeds"], (("mode", "mode"), ("seed", "seed"))),
        "",
        "## Every scenario, both modes",
        "",
        *_table(results["scenarios"], (("scenario", "scenario"), ("vehicles", "vehicles"), ("mode", "mode"), ("seed", "seed"))),
        "",
        "Wall time per run (lockstep, this machine): "
        + ", ".join(f"{r['scenario']}/{r['mode']} {r['wall_s']:.0f} s" for r in results["scenarios"]) + ".",
        "",
        "## ṗ feed-forward readings of eq 5 on `circle` (SPEC §2)",
        "",
        "`normal`: only the edge-normal part of ṗ (both modes' default); `full`: ṗ as printed (its tangential part is",
        "the drone's own sliding along the edge, i.e. positive feedback); `none`: no feed-forward.",
        "",
        *_table(results["pdot"], (("label", "run"),)),
        "",
    ]
    return "\n".join(out)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m gcs.results_table", description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/RESULTS.md"))
    parser.add_argument("--scenarios", nargs="*", default=None, help="default: every bundled scenario")
    parser.add_argument("--seeds", type=int, nargs="*", default=[1, 2, 3, 4, 5])
    parser.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    ns = parser.parse_args(argv)
    names = ns.scenarios if ns.scenarios is not None else scenario_names()
    unknown = [n for n in names if n not in scenario_names()]
    if unknown:
        print(f"gcs.results_table: unknown scenario {unknown[0]!r}", file=sys.stderr)
        return 2
    start = time.perf_counter()
    results = build_results(names, ns.seeds, lambda msg: print(msg, file=sys.stderr, flush=True), ns.jobs)
    command = "python -m gcs.results_table" + ("" if argv is None else " " + " ".join(argv))
    if argv is None and len(sys.argv) > 1:
        command = "python -m gcs.results_table " + " ".join(sys.argv[1:])
    ns.out.parent.mkdir(parents=True, exist_ok=True)
    ns.out.write_text(render_markdown(results, ns.seeds, command, time.perf_counter() - start), encoding="utf-8")
    print(f"wrote {ns.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
