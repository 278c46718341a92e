"""What perception costs onboard, in flight: each agent's thread CPU time per camera frame (p50 / p95), read from
the exit line it writes to its log, in one mission of the processes engine.

    .venv/bin/python -m bench.perception_in_flight circle --set weather=moderate \
        --set imaging.turbid_water_probability=1 [--duration 60] [--out DIR]

The mission is ``python -m gcs.mission SCENARIO --out DIR --no-live --no-dashboard`` with the given options, a
child of this process (a Ctrl-C reaches it too; this waits for its own shutdown, then stops it). Loopback only; run
it inside ``unshare -n`` beside other missions. Where ``bench.perception_conditions`` perceives each frame right
after the renderer drew it in the same thread, here the frame comes from the camera process and the agent's thread
has just run its control tick, as on a companion computer. Prints one row per agent that perceived frames and the
fleet's median of the agents' p50s.
"""

from __future__ import annotations

import argparse
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from bench.camera_perception import machine
from gcs.processes.agent_exit_report import perception_cpu_in_log

REPO = Path(__file__).resolve().parents[1]
_FRAMES = re.compile(r"vehicle (\d+) exits with -?\d+: .* (\d+) frames processed")
SHUTDOWN_WAIT_S = 30.0


def run_mission(scenario: str, options: list[str], out: Path) -> int:
    """The mission's exit code; on Ctrl-C the mission shuts down by itself first (it got the signal too)."""
    proc = subprocess.Popen([sys.executable, "-m", "gcs.mission", scenario, *options, "--out", str(out),
                             "--no-live", "--no-dashboard"], cwd=REPO)
    try:
        return proc.wait()
    except KeyboardInterrupt:
        try:
            proc.wait(timeout=SHUTDOWN_WAIT_S)
        except subprocess.TimeoutExpired:
            proc.terminate()
            proc.wait()
        raise


def agent_rows(out: Path) -> list[tuple[int, int, float, float]]:
    """(vehicle id, frames processed, p50 [ms], p95 [ms]) of every agent whose log holds an exit line with frames."""
    rows = []
    for log in sorted(out.glob("agent_*.log"), key=lambda p: int(p.stem.split("_")[1])):
        vehicle_id = int(log.stem.split("_")[1])
        text = log.read_text(errors="replace")
        cpu = perception_cpu_in_log(text, vehicle_id)
        frames = [int(m.group(2)) for m in _FRAMES.finditer(text) if int(m.group(1)) == vehicle_id]
        if cpu is not None and frames and frames[-1] > 0 and math.isfinite(cpu[0]):
            rows.append((vehicle_id, frames[-1], cpu[0], cpu[1]))
    return rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenario")
    parser.add_argument("--set", action="append", default=[], dest="settings", metavar="KEY=VALUE")
    parser.add_argument("--duration", type=float, default=None, help="simulated seconds (default: scenario)")
    parser.add_argument("--seed", type=int, default=None)
    parser.add_argument("--out", type=Path, default=None, help="the mission's output folder (default: a temporary one)")
    args = parser.parse_args()
    options = [f"--set={s}" for s in args.settings]
    options += [] if args.duration is None else ["--duration", str(args.duration)]
    options += [] if args.seed is None else ["--seed", str(args.seed)]
    print(machine(), flush=True)
    with tempfile.TemporaryDirectory(prefix="perception_in_flight_") as scratch:
        out = args.out if args.out is not None else Path(scratch)
        code = run_mission(args.scenario, options, out)
        rows = agent_rows(out)
    print(f"mission exit code {code}; {machine()}")
    if not rows:
        print("no agent reported perceiving a frame", file=sys.stderr)
        return 1
    print("| vehicle | frames perceived | perception CPU p50 [ms] | p95 [ms] |\n|---|---|---|---|")
    for vehicle_id, frames, p50, p95 in rows:
        print(f"| {vehicle_id} | {frames} | {p50:.2f} | {p95:.2f} |")
    p50s = [r[2] for r in rows]
    print(f"median over {len(rows)} agents of their p50: {float(np.median(p50s)):.2f} ms (range "
          f"{min(p50s):.2f}-{max(p50s):.2f}); largest p95 {max(r[3] for r in rows):.2f} ms")
    return 0 if code == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
