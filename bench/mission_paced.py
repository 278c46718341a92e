"""Benchmark of the paced clock: whole missions as processes, beside the lockstep engine, on this machine.

For each case it runs ``python -m gcs.mission SCENARIO --engine lockstep`` (the reference) and the processes engine
(``--clock paced`` unless the case says ``free``), then prints side by side: wall time, the achieved real-time factor
and the time the clock stood waiting (from metrics.json's ``engine_health``), both verdicts, the headline metrics and the
disagreements under ``gcs.metrics.agreement``'s tolerances. While the processes run it samples every agent's memory
from ``/proc/<pid>/smaps_rollup`` (PSS: shared libraries counted once across the fleet, unlike RSS) and reports the
median per agent and the peak of the whole run's PSS.

Usage::

    python bench/mission_paced.py --cases "circle:speed=3"
    python bench/mission_paced.py --cases "circle:speed=3;circle:speed=3,clock=free;large:backend=kinematic"

Ports 28000-28999 are used so the benchmark never meets a running mission or the tests.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from bench.agent_tick_cost import pss_mb  # noqa: E402
from gcs.metrics.agreement import disagreements  # noqa: E402

SHOWN = ("encircle_time_s", "polygon_iou_final", "coverage_final", "spacing_cv_final", "tracking_rms_last_10s_m",
         "min_pairwise_distance_m", "near_miss_pairs")


@dataclass
class MemorySampler:
    """Samples PSS [MiB] of a run's processes every ``period_s`` while ``processes.json`` lists them."""

    out_dir: Path
    period_s: float = 5.0
    agent_pss_mib: list[float] = field(default_factory=list)
    total_pss_peak_mib: float = 0.0
    agents_seen_peak: int = 0
    _stop: threading.Event = field(default_factory=threading.Event)

    def run(self) -> None:
        while not self._stop.wait(self.period_s):
            try:
                pids = json.loads((self.out_dir / "processes.json").read_text())
            except (OSError, ValueError):
                continue
            total, agents = 0.0, []
            for name, pid in pids.items():
                pss = pss_mb(pid)
                if pss is None:
                    continue
                total += pss
                if name.startswith("agent_"):
                    agents.append(pss)
            if len(agents) >= self.agents_seen_peak:
                self.agents_seen_peak = len(agents)
                self.agent_pss_mib = agents
            self.total_pss_peak_mib = max(self.total_pss_peak_mib, total)

    def stop(self) -> None:
        self._stop.set()


def run_mission(args: list[str], out: Path, base_port: int) -> tuple[int, float, dict]:
    env = dict(os.environ, FLOODWATCH_ZENOH_ENDPOINT=f"tcp/127.0.0.1:{base_port + 60}", PYTHONUNBUFFERED="1")
    started = time.monotonic()
    proc = subprocess.run([sys.executable, "-m", "gcs.mission", *args, "--out", str(out), "--no-live",
                           "--base-port", str(base_port), "--gcs-port", str(base_port + 50)],
                          cwd=REPO, env=env, capture_output=True, text=True)
    wall_s = time.monotonic() - started
    try:
        metrics = json.loads((out / "metrics.json").read_text())
    except (OSError, ValueError):
        metrics = {}
    if proc.returncode != 0:
        print(proc.stdout[-1500:], proc.stderr[-1500:], file=sys.stderr)
    return proc.returncode, wall_s, metrics


def parse_case(text: str) -> tuple[str, dict[str, str]]:
    scenario, _, rest = text.partition(":")
    options = dict(item.split("=", 1) for item in rest.split(",") if item)
    return scenario.strip(), options


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", default="circle:speed=3",
                        help='";"-separated SCENARIO[:speed=S,clock=C,mode=M,backend=B,reference=DIR,agent_timeout=T] '
                             '(B: the lockstep reference\'s vehicle backend, px4 by default; DIR: a lockstep run '
                             'already made; T: the processes run\'s --agent-timeout-s)')
    parser.add_argument("--out", type=Path, default=Path("/tmp/fw_bench_paced"))
    ns = parser.parse_args()
    print(f"machine: {platform.processor() or platform.machine()}, {len(os.sched_getaffinity(0))} cores, "
          f"load {os.getloadavg()[0]:.1f}")
    for index, case in enumerate(ns.cases.split(";")):
        scenario, options = parse_case(case)
        mode = options.get("mode", "improved")
        speed = options.get("speed", "1")
        clock = options.get("clock", "paced")
        backend = options.get("backend", "px4")
        base = 28000 + 100 * index
        if "reference" in options:
            ref_code, ref_wall_s = 0, float("nan")
            ref = json.loads((Path(options["reference"]) / "metrics.json").read_text())
        else:
            ref_code, ref_wall_s, ref = run_mission(
                [scenario, "--engine", "lockstep", "--backend", backend, "--mode", mode], ns.out / f"{index}-lockstep", base)
        out = ns.out / f"{index}-processes"
        sampler = MemorySampler(out)
        thread = threading.Thread(target=sampler.run, daemon=True)
        thread.start()
        timeout = ["--agent-timeout-s", options["agent_timeout"]] if "agent_timeout" in options else []
        code, wall_s, metrics = run_mission([scenario, "--mode", mode, "--speed", speed, "--clock", clock, *timeout],
                                            out, base)
        sampler.stop()
        thread.join()
        engine, safety = metrics.get("engine_health", {}), metrics.get("safety", {})
        summary, ref_summary = metrics.get("summary", {}), ref.get("summary", {})
        print(f"\n== {scenario} mode={mode} speed={speed} clock={clock} {' '.join(timeout)}")
        print(f"lockstep ({backend} backend): exit {ref_code}, {ref_wall_s:.0f} s wall")
        print(f"processes: exit {code}, {wall_s:.0f} s wall, achieved {engine.get('real_time_factor')}x real time, "
              f"clock held {engine.get('held_wall_s')} s, slowest wait {engine.get('slowest_wait_wall_s')} s")
        print(f"  engine: {engine.get('health')} {engine.get('reasons')}; agents >= {engine.get('agent_rate_min_hz')} Hz "
              f"of {engine.get('agent_rate_nominal_hz')}, cameras {engine.get('camera_rate_hz')} Hz")
        print(f"  safety: {safety.get('failsafe_count')} failsafes, {safety.get('near_miss_pairs')} pairs < 1 m, "
              f"closest {safety.get('closest_approach_m')} m")
        if sampler.agent_pss_mib:
            print(f"  memory: {sampler.agents_seen_peak} agents, PSS per agent median "
                  f"{statistics.median(sampler.agent_pss_mib):.1f} MiB (PSS splits each shared page among the processes mapping it), "
                  f"whole run PSS peak {sampler.total_pss_peak_mib / 1024:.2f} GiB")
        for key in SHOWN:
            print(f"  {key:28s} lockstep {ref_summary.get(key)!s:>22}  processes {summary.get(key)!s:>22}")
        print(f"  disagreements: {disagreements(ref_summary, summary) if ref_summary and summary else 'n/a'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
