"""Campaign throughput: N ``circle`` runs as a campaign (1 and 2 workers) against the same runs in a plain loop.

    .venv/bin/python bench/campaign_throughput.py --runs 4

The plain loop is what a script calling ``gcs.lockstep.engine.run_lockstep`` and ``compute_mission_metrics`` in one
process does (OpenCV at one thread, as in the campaign's workers); the campaign adds process start-up, the local
cluster, shipping each row back and writing it as Parquet, and the summary and plots at the end. Prints a Markdown
table: wall and CPU seconds (CPU of every process involved), seconds per run, missions per hour, and the overhead
per run against the plain loop.
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def children_cpu_s() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def plain_loop(runs: int, mode: str, duration_s: float | None) -> tuple[float, float]:
    """(wall, CPU) seconds of ``runs`` lockstep runs and their metrics, one after the other in this process."""
    import cv2

    from gcs.lockstep.engine import run_lockstep
    from gcs.metrics.mission import compute_mission_metrics
    from gcs.scenario import load_scenario

    cv2.setNumThreads(1)
    extra = [f"duration_s={duration_s}"] if duration_s else []
    wall_start, cpu_start = time.perf_counter(), time.process_time()
    for seed in range(1, runs + 1):
        scenario = load_scenario("circle", [*extra, f"seed={seed}"])
        result = run_lockstep(scenario, mode)
        compute_mission_metrics(result.record, result.flood, scenario.camera.fov_deg)
    return time.perf_counter() - wall_start, time.process_time() - cpu_start


def campaign(runs: int, mode: str, duration_s: float | None, workers: int, out: Path) -> tuple[float, float, float]:
    """(wall, CPU, CPU inside the runs) seconds of the same runs as ``python -m gcs.campaign`` with ``workers``.

    The last is the sum of the rows' ``cpu_s`` (each run's own process time in its worker); the rest of the CPU is
    the campaign's: interpreter and cluster start-up, scheduler and nannies, rows, summary and plots.
    """
    from gcs.campaign.store import read_rows

    extra = ["--set", f"duration_s={duration_s}"] if duration_s else []
    cpu_before = children_cpu_s()
    wall_start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "gcs.campaign", "circle", "--seeds", f"1-{runs}", "--mode", mode, *extra,
                    "--workers", str(workers), "--out", str(out)], cwd=REPO, check=True, stdout=subprocess.DEVNULL)
    wall_s, cpu_s = time.perf_counter() - wall_start, children_cpu_s() - cpu_before
    return wall_s, cpu_s, sum(float(row["cpu_s"]) for row in read_rows(out))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=4, help="circle runs per configuration (seeds 1..N)")
    parser.add_argument("--mode", default="improved")
    parser.add_argument("--duration", type=float, default=None, metavar="S", help="simulated seconds (default 60)")
    ns = parser.parse_args()
    results: list[tuple[str, float, float, float]] = []
    wall, cpu = plain_loop(ns.runs, ns.mode, ns.duration)
    results.append(("plain loop (run_lockstep + metrics)", wall, cpu, cpu))
    print(f"plain: {wall:.1f} s wall, {cpu:.1f} s CPU", file=sys.stderr, flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        for workers in (1, 2):
            wall, cpu, runs_cpu = campaign(ns.runs, ns.mode, ns.duration, workers, Path(tmp) / f"w{workers}")
            results.append((f"campaign, {workers} worker{'s' if workers > 1 else ''}", wall, cpu, runs_cpu))
            print(f"campaign {workers}: {wall:.1f} s wall, {cpu:.1f} s CPU, {runs_cpu:.1f} s CPU in the runs",
                  file=sys.stderr, flush=True)
    plain_wall, plain_cpu = results[0][1], results[0][2]
    print(f"| {ns.runs} `circle` runs, {ns.mode} | wall [s] | CPU [s] | CPU in the runs [s] | wall per run [s] | "
          "missions per hour | overhead per run vs plain, wall / CPU [s] | campaign's own CPU [s] | wall vs plain |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, wall, cpu, runs_cpu in results:
        per_run = wall / ns.runs
        overhead = f"{(wall - plain_wall) / ns.runs:+.1f} / {(cpu - plain_cpu) / ns.runs:+.1f}"
        own = "—" if wall == plain_wall else f"{cpu - runs_cpu:.1f}"
        print(f"| {name} | {wall:.1f} | {cpu:.1f} | {runs_cpu:.1f} | {per_run:.1f} | {3600.0 / per_run:.0f} | "
              f"{'—' if wall == plain_wall else overhead} | {own} | {wall / plain_wall:.2f}x |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
