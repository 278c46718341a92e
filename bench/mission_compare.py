"""Do the two engines agree? The same scenario, mode and seed through lockstep and through processes.

Both engines run the same onboard core (``vehicle_agents.core.onboard.onboard_step``): the lockstep engine for the
whole fleet in one process on one clock, by default on the mock PX4 itself (``--backend px4``: the same sans-IO
vehicle, modes and failsafes the fleet process runs); the processes engine in one agent process per drone over real
MAVLink (MAVSDK) and Zenoh, with take-off, transport delays, camera frames up to one period old and a radio that
relays through the emulator. The table says how far apart their metrics end up, next to the tolerances
:data:`TOLERANCES` we hold the processes engine to.

Usage::

    python bench/mission_compare.py                      # the seven cases of CASES, improved mode, seed 1
    python bench/mission_compare.py --cases circle --modes paper,improved --backend kinematic

A case is ``scenario`` or ``scenario:key=value[,key=value]`` (``--set`` overrides for both engines).
Ports 28000-28999 are used.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from gcs.metrics.agreement import TOLERANCES, within  # noqa: E402

CASES = (
    "circle", "ellipse", "nonconvex", "drift", "terrain",
    "circle:radio.loss=0.3", "circle:kinematics.response_time_s=0.6",
)
"""The issue's agreement set: every small scenario, and circle with a lossy radio and with a slower vehicle."""


def run_engine(engine: str, case: str, mode: str, seed: int, speed: float, out: Path, duration_s: float | None,
               backend: str) -> dict:
    scenario, _, sets = case.partition(":")
    args = [sys.executable, "-m", "gcs.mission", scenario, "--engine", engine, "--mode", mode, "--seed", str(seed),
            "--out", str(out), "--no-live", "--base-port", "28000", "--gcs-port", "28900"]
    for assignment in filter(None, sets.split(",")):
        args += ["--set", assignment]
    if engine == "processes":
        args += ["--speed", f"{speed:g}"]
    else:
        args += ["--backend", backend]
    if duration_s is not None:
        args += ["--duration", f"{duration_s:g}"]
    env = {"FLOODWATCH_ZENOH_ENDPOINT": "tcp/127.0.0.1:28960"}
    proc = subprocess.run(args, cwd=REPO, capture_output=True, text=True, timeout=1800,
                          env={**__import__("os").environ, **env})
    if proc.returncode != 0:
        raise RuntimeError(f"{engine} {case} {mode} failed ({proc.returncode}): {proc.stderr[-1000:]}")
    return json.loads((out / "metrics.json").read_text())["summary"]


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", default=";".join(CASES), help="cases separated by ';' (default: CASES)")
    p.add_argument("--modes", default="improved")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--speed", type=float, default=1.0)
    p.add_argument("--duration", type=float, default=None)
    p.add_argument("--backend", choices=("px4", "kinematic"), default="px4", help="the lockstep run's vehicles")
    p.add_argument("--out", type=Path, default=REPO / "runs" / "bench-compare")
    args = p.parse_args()
    metrics = list(TOLERANCES)
    print(f"lockstep --backend {args.backend} vs processes, seed {args.seed}; each cell lockstep / processes")
    print("| case | mode | " + " | ".join(metrics) + " | ok |")
    print("|---|---|" + "---|" * len(metrics) + "---|")
    all_ok = True
    for case in filter(None, args.cases.split(";")):
        for mode in args.modes.split(","):
            folder = case.replace(":", "-").replace("=", "").replace(",", "-")
            results = {engine: run_engine(engine, case, mode, args.seed, args.speed,
                                          args.out / f"{folder}-{mode}-{engine}", args.duration, args.backend)
                       for engine in ("lockstep", "processes")}
            cells, failed = [], []
            for metric in metrics:
                a, b = results["lockstep"].get(metric), results["processes"].get(metric)
                if not within(metric, a, b):
                    failed.append(metric)
                cells.append(f"{_fmt(a)} / {_fmt(b)}")
            all_ok &= not failed
            print(f"| {case} | {mode} | " + " | ".join(cells) + f" | {'yes' if not failed else 'NO: ' + ', '.join(failed)} |",
                  flush=True)
    print("tolerances: " + ", ".join(f"{m} {'±' if k == 'abs' else '>= '}{b:g}" for m, (k, b) in TOLERANCES.items()))
    return 0 if all_ok else 1


def _fmt(value: object) -> str:
    return f"{value:.3f}" if isinstance(value, float) else str(value)


if __name__ == "__main__":
    sys.exit(main())
