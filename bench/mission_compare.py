"""Do the two engines agree? The same scenario, mode and seed through lockstep and through processes.

The lockstep engine is the deterministic reference (one process, one clock, no take-off); the processes engine flies
the same control-law code in 13 agent processes over real MAVLink and Zenoh, with take-off, transport delays, camera
frames that are up to one period old and a radio that relays through the emulator. The table says how far apart
their metrics end up, next to the tolerances :data:`TOLERANCES` we hold the processes engine to.

Usage::

    python bench/mission_compare.py --scenario circle --modes paper,improved --speed 1

Ports 28000-28999 are used.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

TOLERANCES: dict[str, tuple[str, float]] = {
    "encircle_time_s": ("abs", 2.0),
    "polygon_iou_final": ("abs", 0.02),
    "coverage_final": ("abs", 0.05),
    "spacing_cv_final": ("abs", 0.05),
    "tracking_rms_last_10s_m": ("abs", 0.3),
    "leader_centring_error_final_m": ("abs", 0.5),
    "min_pairwise_distance_m": ("floor", 1.0),
}
"""Metric -> (kind, bound): ``abs`` = |processes - lockstep| <= bound; ``floor`` = both engines >= bound."""


def run_engine(engine: str, scenario: str, mode: str, seed: int, speed: float, out: Path, duration_s: float | None) -> dict:
    args = [sys.executable, "-m", "gcs.mission", scenario, "--engine", engine, "--mode", mode, "--seed", str(seed),
            "--out", str(out), "--no-live", "--base-port", "28000", "--gcs-port", "28900"]
    if engine == "processes":
        args += ["--speed", f"{speed:g}"]
    if duration_s is not None:
        args += ["--duration", f"{duration_s:g}"]
    env = {"FLOODWATCH_ZENOH_ENDPOINT": "tcp/127.0.0.1:28960"}
    proc = subprocess.run(args, cwd=REPO, capture_output=True, text=True, timeout=1800,
                          env={**__import__("os").environ, **env})
    if proc.returncode != 0:
        raise RuntimeError(f"{engine} {scenario} {mode} failed ({proc.returncode}): {proc.stderr[-1000:]}")
    return json.loads((out / "metrics.json").read_text())["summary"]


def within(metric: str, lockstep: float | None, processes: float | None) -> bool:
    kind, bound = TOLERANCES[metric]
    if lockstep is None or processes is None or not (math.isfinite(lockstep) and math.isfinite(processes)):
        return lockstep == processes
    if kind == "abs":
        return abs(processes - lockstep) <= bound
    return lockstep >= bound and processes >= bound


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="circle")
    p.add_argument("--modes", default="paper,improved")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--speed", type=float, default=1.0)
    p.add_argument("--duration", type=float, default=None)
    p.add_argument("--out", type=Path, default=REPO / "runs" / "bench-compare")
    args = p.parse_args()
    print("| scenario | mode | metric | lockstep | processes | tolerance | ok |")
    print("|---|---|---|---|---|---|---|")
    all_ok = True
    for mode in args.modes.split(","):
        results = {engine: run_engine(engine, args.scenario, mode, args.seed, args.speed,
                                      args.out / f"{args.scenario}-{mode}-{engine}", args.duration)
                   for engine in ("lockstep", "processes")}
        for metric, (kind, bound) in TOLERANCES.items():
            a, b = results["lockstep"].get(metric), results["processes"].get(metric)
            ok = within(metric, a, b)
            all_ok &= ok
            tol = f"±{bound:g}" if kind == "abs" else f">= {bound:g}"
            print(f"| {args.scenario} | {mode} | {metric} | {_fmt(a)} | {_fmt(b)} | {tol} | {'yes' if ok else 'NO'} |",
                  flush=True)
    return 0 if all_ok else 1


def _fmt(value: object) -> str:
    return f"{value:.3f}" if isinstance(value, float) else str(value)


if __name__ == "__main__":
    sys.exit(main())
