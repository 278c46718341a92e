"""``python -m gcs.campaign``: every seed x mode x grid cell of a scenario as a lockstep run on dask.distributed.

The shell around the pure parts: check every argument and every grid cell's scenario before anything starts
(one line and exit 2 otherwise), start or join a cluster, submit the runs not done yet, write each row as its run
finishes, show progress, then write ``summary.md`` and the box plots. Ctrl-C closes the cluster; the rows written
stay, and the same command resumes.
"""

from __future__ import annotations

import argparse
import os
import shlex
import signal
import subprocess
import sys
import time
from collections.abc import Sequence
from concurrent.futures import TimeoutError as FuturesTimeoutError
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from gcs.campaign.grid import CampaignSyntaxError, GridAxis, Mode, RunSpec, check_axes, expand, parse_assignment_key
from gcs.campaign.grid import parse_grid_axis, parse_modes, parse_seeds
from gcs.campaign.progress import Counts, ProgressView
from gcs.campaign.runner import ERROR_COLUMN, base_row, run_one
from gcs.campaign.store import done_run_ids, read_rows, write_row
from gcs.one_line_argparse import EXIT_USAGE, OneLineArgumentParser
from gcs.scenario import ScenarioError, load_scenario

LABEL = "gcs.campaign"
EXIT_OK = 0
EXIT_RUNS_FAILED = 1
EXIT_INTERRUPTED = 130
DEFAULT_RETRIES = 2

EPILOG = """\
Reports: `python -m gcs.campaign report OUT [OUT ...]` rewrites OUT/summary.md and OUT/plots/*.png from the rows
alone (several folders: one summary of all their rows, written into the first).

Exit codes: 0 every run ok; 1 some runs failed (each has a row with its error); 2 bad arguments, nothing started;
130 interrupted (the rows written stay: rerun the same command to resume).

Rows: OUT/rows/<run_id>.parquet, one per run, written as it finishes; run_id hashes scenario, mode, seed and the
sorted grid and --set assignments. A run whose row exists (ok or failed) is skipped; delete its file to rerun it.
"""


@dataclass(frozen=True)
class CampaignOptions:
    """A parsed and checked campaign command."""

    scenario: str
    runs: tuple[RunSpec, ...]
    out_dir: Path
    workers: int
    scheduler: str | None
    keep_outputs: bool
    retries: int


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineArgumentParser(
        prog="python -m gcs.campaign", label=LABEL, epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Run a scenario over seeds x modes x a grid of overrides (lockstep engine, dask.distributed).")
    parser.add_argument("scenario", help="bundled scenario name (circle, ellipse, ...) or path to a .toml file")
    parser.add_argument("--seeds", default=None, metavar="LIST",
                        help="seeds, e.g. 1-20 or 1,4,9-12 (default: the scenario's own seed)")
    parser.add_argument("--mode", default="paper,improved", metavar="MODES",
                        help="comma-separated modes (default: paper,improved)")
    parser.add_argument("--grid", action="append", default=[], metavar="KEY=V1,V2",
                        help="a scenario key and its values, e.g. radio.loss=0,0.3 (repeatable: every combination)")
    parser.add_argument("--set", dest="fixed", action="append", default=[], metavar="KEY=VALUE",
                        help="override for every run, e.g. --set duration_s=30 (repeatable)")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR", help="campaign folder (rows, summary, plots)")
    parser.add_argument("--workers", type=int, default=None, metavar="N",
                        help="local worker processes, one thread each (default: the CPU count)")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="use a running dask scheduler, e.g. tcp://HOST:8786, instead of a local cluster "
                             "(its workers must see OUT with --keep-outputs)")
    parser.add_argument("--keep-outputs", action="store_true",
                        help="also write each run's metrics.json, plots, animation and record into OUT/runs/<run_id>/")
    parser.add_argument("--retries", type=int, default=DEFAULT_RETRIES, metavar="N",
                        help=f"resubmissions of a run whose task raised outside the run (default {DEFAULT_RETRIES}); "
                             "a run on a worker that died is started again by the scheduler")
    return parser


def usage_error(message: str) -> int:
    print(f"{LABEL}: {message}", file=sys.stderr)
    return EXIT_USAGE


def parse_options(argv: Sequence[str]) -> CampaignOptions:
    """Parse and check the command; raises CampaignSyntaxError or ScenarioError with a one-line message."""
    ns = build_parser().parse_args(list(argv))
    if ns.workers is not None and ns.workers < 1:
        raise CampaignSyntaxError(f"--workers: must be >= 1, got {ns.workers}")
    if ns.scheduler is not None and ns.workers is not None:
        raise CampaignSyntaxError("--workers: not with --scheduler (the cluster has its own workers)")
    if ns.retries < 0:
        raise CampaignSyntaxError(f"--retries: must be >= 0, got {ns.retries}")
    modes = parse_modes(ns.mode)
    axes = [parse_grid_axis(text) for text in ns.grid]
    for item in ns.fixed:
        parse_assignment_key(item, "--set")
    check_axes(axes, ns.fixed)
    base = load_scenario(ns.scenario, ns.fixed)
    seeds = parse_seeds(ns.seeds) if ns.seeds is not None else (base.seed,)
    runs = expand(ns.scenario, modes, seeds, axes, ns.fixed)
    check_cells(ns.scenario, axes, runs)
    workers = ns.workers if ns.workers is not None else max(1, _cpu_count())
    return CampaignOptions(ns.scenario, tuple(runs), ns.out, workers, ns.scheduler, ns.keep_outputs, ns.retries)


def check_cells(scenario: str, axes: Sequence[GridAxis], runs: Sequence[RunSpec]) -> None:
    """Resolve the scenario of every grid cell (at the first seed) and build its models; raises ScenarioError."""
    from gcs.lockstep.run import check_models

    checked: set[tuple[tuple[str, str], ...]] = set()
    for spec in runs:
        if spec.cell in checked:
            continue
        checked.add(spec.cell)
        try:
            check_models(load_scenario(scenario, spec.overrides()))
        except ScenarioError as exc:
            raise ScenarioError(_name_the_cell(str(exc), spec, axes)) from None


def _name_the_cell(message: str, spec: RunSpec, axes: Sequence[GridAxis]) -> str:
    """Prefix a scenario error with the ``--grid`` value it came from (or the whole cell when it names none)."""
    for key, value in spec.cell:
        if message.startswith(f"{key}:"):
            return f"--grid {message}" if "unknown key" in message else f"--grid {key}={value}: {message}"
    return f"grid cell {spec.cell_label()}: {message}" if axes else message


def _cpu_count() -> int:
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def code_version() -> str:
    """``git describe --always --dirty`` of the source tree, else the installed package's version."""
    root = Path(__file__).resolve().parents[2]
    try:
        done = subprocess.run(["git", "-C", str(root), "describe", "--always", "--dirty"], capture_output=True,
                              text=True, timeout=10, check=True)
        if done.stdout.strip():
            return done.stdout.strip()
    except (OSError, subprocess.SubprocessError):
        pass
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("floodwatch")
    except PackageNotFoundError:
        return "unknown"


def run_label(spec: RunSpec) -> str:
    cell = "" if not spec.cell else f" [{spec.cell_label()}]"
    return f"{spec.scenario} {spec.mode.value} seed {spec.seed}{cell}"


def finished_line(spec: RunSpec, row: dict[str, Any]) -> str:
    if row.get(ERROR_COLUMN):
        return f"FAILED {run_label(spec)}: {row[ERROR_COLUMN]}"
    return f"ok {run_label(spec)}: {row.get('wall_s', 0.0):.1f} s wall, {row.get('cpu_s', 0.0):.1f} s CPU"


def write_reports(out_dirs: Sequence[Path]) -> list[dict[str, Any]]:
    """``summary.md`` and ``plots/`` in the first folder, from the rows of all of them; returns the rows."""
    from gcs.campaign.plots import write_box_plots
    from gcs.campaign.summary import summary_markdown

    rows = read_rows(*out_dirs)
    target = out_dirs[0]
    target.mkdir(parents=True, exist_ok=True)
    (target / "summary.md").write_text(summary_markdown(rows), encoding="utf-8")
    write_box_plots(rows, target / "plots")
    return rows


def report_main(argv: Sequence[str]) -> int:
    parser = OneLineArgumentParser(prog="python -m gcs.campaign report", label=LABEL,
                                   description="Rewrite summary.md and plots/ of campaign folders from their rows.")
    parser.add_argument("out", type=Path, nargs="+", metavar="OUT", help="campaign folder(s)")
    ns = parser.parse_args(list(argv))
    missing = [str(p) for p in ns.out if not (p / "rows").is_dir()]
    if missing:
        return usage_error(f"report: no rows in {missing[0]} (expected {missing[0]}/rows/*.parquet)")
    rows = write_reports(ns.out)
    print(f"{len(rows)} rows -> {ns.out[0] / 'summary.md'}, {ns.out[0] / 'plots'}")
    return EXIT_OK


class Cluster:
    """A dask client on a local cluster (closed on exit) or on a running scheduler (left running)."""

    def __init__(self, workers: int, scheduler: str | None) -> None:
        self.workers = workers
        self.scheduler = scheduler
        self.cluster: Any = None
        self.client: Any = None

    def __enter__(self) -> Any:
        from dask.distributed import Client, LocalCluster

        if self.scheduler is not None:
            self.client = Client(self.scheduler, timeout="30s")
        else:
            self.cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True,
                                        dashboard_address=":0", memory_limit=0, silence_logs=40)
            self.client = Client(self.cluster)
        return self.client

    def __exit__(self, *exc: object) -> None:
        try:
            if self.client is not None:
                self.client.close()
        finally:
            if self.cluster is not None:
                self.cluster.close()


def run_campaign(options: CampaignOptions, stream: Any = None) -> int:
    """Run the runs that have no row yet; write rows as they finish, then the reports. Returns the exit code."""
    out = options.out_dir
    out.mkdir(parents=True, exist_ok=True)
    with (out / "commands.txt").open("a", encoding="utf-8") as log:
        log.write(shlex.join(["python", "-m", "gcs.campaign", *sys.argv[1:]]) + "\n")
    done = done_run_ids(out)
    todo = [spec for spec in options.runs if spec.run_id not in done]
    version = code_version()
    stream = stream or sys.stdout
    print(f"{LABEL}: {len(options.runs)} runs, {len(options.runs) - len(todo)} already done, {len(todo)} to run; "
          f"code {version}; {'scheduler ' + options.scheduler if options.scheduler else f'{options.workers} local workers'}",
          file=stream, flush=True)
    interrupted = False
    if todo:
        try:
            _submit_and_collect(options, todo, version, len(options.runs) - len(todo), stream)
        except KeyboardInterrupt:
            interrupted = True
            print(f"{LABEL}: interrupted; {len(done_run_ids(out))} rows kept in {out / 'rows'} "
                  "(run the same command to resume)", file=sys.stderr, flush=True)
    planned = {spec.run_id for spec in options.runs}
    rows = write_reports([out])
    mine = [row for row in rows if row.get("run_id") in planned]
    failed = [row for row in mine if row.get(ERROR_COLUMN)]
    print(f"{LABEL}: {len(mine)}/{len(planned)} rows, {len(failed)} failed -> {out / 'summary.md'}", file=stream,
          flush=True)
    if interrupted:
        return EXIT_INTERRUPTED
    return EXIT_RUNS_FAILED if failed or len(mine) < len(planned) else EXIT_OK


def _submit_and_collect(options: CampaignOptions, todo: Sequence[RunSpec], version: str, skipped: int,
                        stream: Any) -> None:
    from dask.distributed import wait

    out = options.out_dir
    with Cluster(options.workers, options.scheduler) as client:
        by_key: dict[str, RunSpec] = {}
        pending = set()
        for spec in todo:
            outputs = str((out / "runs" / spec.run_id).resolve()) if options.keep_outputs else None
            future = client.submit(run_one, spec, version, outputs, key=f"campaign-run-{spec.run_id}",
                                   retries=options.retries, pure=False)
            by_key[future.key] = spec
            pending.add(future)
        done_count = failed_count = 0
        with ProgressView(len(todo), skipped, stream) as view:
            view.update(Counts(len(todo), 0, 0, 0, skipped))
            while pending:
                try:
                    finished = wait(pending, timeout=1.0, return_when="FIRST_COMPLETED").done
                except (FuturesTimeoutError, TimeoutError):
                    finished = set()
                for future in finished:
                    pending.discard(future)
                    spec = by_key[future.key]
                    row = _row_of(future, spec, version)
                    if future.status != "cancelled" and not str(row.get(ERROR_COLUMN)).startswith("KeyboardInterrupt"):
                        write_row(out, spec.run_id, row)
                    done_count += 1
                    failed_count += bool(row.get(ERROR_COLUMN))
                    view.update(Counts(len(todo), done_count, failed_count, _running(client, pending), skipped),
                                finished_line(spec, row))
                if not finished:
                    view.update(Counts(len(todo), done_count, failed_count, _running(client, pending), skipped))


def _row_of(future: Any, spec: RunSpec, version: str) -> dict[str, Any]:
    """The run's row, or a row with the error when the task itself failed (e.g. its worker kept dying).

    A cancelled task (the scheduler went away) or one stopped by Ctrl-C reaching the worker gets a row that is
    shown but not written, so a rerun runs it.
    """
    if future.status == "finished":
        return future.result()
    row = base_row(spec, version)
    try:
        exc = future.exception()
        row[ERROR_COLUMN] = f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
    except Exception as exc:  # noqa: BLE001 - a cancelled future raises instead of returning its exception
        row[ERROR_COLUMN] = f"{type(exc).__name__}: task {future.status}"
    return row


def _running(client: Any, pending: set[Any]) -> int:
    """How many of the pending runs a worker is processing now (0 when the scheduler cannot say)."""
    try:
        processing = client.processing()
        threads = sum(client.nthreads().values())
    except Exception:  # noqa: BLE001 - progress only; a slow scheduler must not stop the campaign
        return 0
    keys = {future.key for future in pending}
    return min(threads, sum(1 for tasks in processing.values() for key in tasks if key in keys))


def main(argv: Sequence[str] | None = None) -> int:
    """Parse and check, then run; returns the process exit code."""
    args = list(sys.argv[1:] if argv is None else argv)
    if args[:1] == ["report"]:
        return report_main(args[1:])
    try:
        options = parse_options(args)
    except (CampaignSyntaxError, ScenarioError) as exc:
        return usage_error(str(exc))
    start_s = time.monotonic()
    previous = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, _interrupt)
    try:
        code = run_campaign(options)
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    print(f"{LABEL}: {time.monotonic() - start_s:.0f} s wall", flush=True)
    return code


def _interrupt(signum: int, frame: object) -> None:
    """SIGTERM as Ctrl-C: close the cluster, keep the rows (also when started in the background with SIGINT ignored)."""
    raise KeyboardInterrupt


__all__ = ["CampaignOptions", "Mode", "build_parser", "main", "parse_options", "run_campaign"]
