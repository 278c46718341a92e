"""Benchmark of the processes engine: does a whole mission hold its speed factor on this machine?

For each speed factor it flies a mission (fleet + bridge, radio, one agent process per vehicle, ground station in
this process) and reports, over the MISSION phase only:

* achieved control rate per agent [Hz of mission time] (from each agent's exit line) and loop overruns;
* setpoint age at the autopilot [mission s], p50/p99: how old the newest offboard setpoint each vehicle holds is,
  sampled by the simulator (what PX4's COM_OF_LOSS_T watchdog looks at; MAVSDK re-sends at 20 Hz wall);
* CPU [% of one core] and peak memory (RSS) per agent, of the fleet+bridge process, the radio and the GCS;
* CPU per agent per control tick [ms], split by thread (``bench/agent_tick_cost.py``: the Python main thread,
  Zenoh's runtimes, MAVSDK's threads), and memory per agent as PSS (shared pages counted once across agents);
* the mission's own metrics (IoU, coverage, encircle time, minimum distance) so a run that "holds" also works.

Usage::

    python bench/mission_processes.py --speeds 1,2,4 --duration 30
    python bench/mission_processes.py --scenario circle --speeds 1 --sizes 4,6,8,10   # boundary drones per group
    python bench/mission_processes.py --scenario large --sizes 8,11,14 --set control_rate_hz=10

Ports 27000-27999 are used so the benchmark never meets a running mission.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import re
import statistics
import sys
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.agent_tick_cost import (  # noqa: E402
    ThreadCpuWindow,
    label_threads_gdb,
    per_tick,
    median_table,
    per_tick_ms,
    pss_mb,
)
from gcs.processes import ProcessOptions  # noqa: E402
from gcs.processes.ground_station import GroundStation  # noqa: E402
from gcs.scenario import load_scenario  # noqa: E402

_CLK_TCK = os.sysconf("SC_CLK_TCK")
BASE_PORT = 27000
GCS_PORT = 27900
ZENOH_ENDPOINT = "tcp/127.0.0.1:27960"
_RATE_RE = re.compile(r"(\d+) control steps \(([\d.]+|nan) Hz mission time\), (\d+) overruns")
_FRAMES_RE = re.compile(r"camera frame rate ([\d.]+|nan) Hz per airborne vehicle \(nominal ([\d.]+) Hz")
_AGE_RE = re.compile(r"setpoint age at the autopilot \[mission s\]: p50 ([\d.]+) p99 ([\d.]+) max ([\d.]+)")


def cpu_seconds(pid: int) -> float | None:
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return None
    return (int(fields[11]) + int(fields[12])) / _CLK_TCK


def rss_mb(pid: int) -> float | None:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    except OSError:
        return None
    return None


def run_once(scenario_name: str, overrides: tuple[str, ...], speed: float, duration_s: float, out_dir: Path,
             mode: str, gdb_labels: bool = False, clock: str = "paced", idle_s: float = 0.0,
             startup_timeout_s: float = 180.0) -> dict[str, object]:
    """Fly one mission and measure it; ``gdb_labels`` names MAVSDK's unnamed threads from one agent's stacks,
    read during take-off (gdb pauses that agent for about a second, outside the measured MISSION phase).

    ``idle_s`` > 0 (paced clock): first hold the clock for that many wall seconds once the MISSION phase has begun
    and measure what every process costs while nothing moves (``bench/agent_idle_cost.py``); the per-tick window
    starts after it. The agent timeout is then longer than the hold, so the holding participant is never left behind.
    """
    scenario = load_scenario(scenario_name, overrides)
    agent_timeout_s = max(2.0, idle_s + 30.0) if idle_s > 0 else 2.0
    options = ProcessOptions(scenario_arg=scenario_name, overrides=overrides, mode=mode, speed=speed,
                             duration_s=duration_s, out_dir=out_dir, mission="bench", mavlink_base_port=BASE_PORT,
                             gcs_port=GCS_PORT, zenoh_endpoint=ZENOH_ENDPOINT, live=False,
                             startup_timeout_s=startup_timeout_s, clock=clock, agent_timeout_s=agent_timeout_s)
    out_dir.mkdir(parents=True, exist_ok=True)
    station = GroundStation(scenario, options, out_dir)
    result: dict[str, int] = {}
    thread = threading.Thread(target=lambda: result.setdefault("code", asyncio.run(station.run())))
    wall_start = time.monotonic()
    thread.start()
    start_cpu: dict[str, float] = {}
    last_cpu: dict[str, float] = {}
    peak_rss: dict[str, float] = {}
    pss_samples: dict[str, list[float]] = {}
    thread_windows: dict[str, ThreadCpuWindow] = {}
    reference: tuple[int, dict[int, str]] | None = None
    gdb_thread: threading.Thread | None = None
    mission_wall = [0.0, 0.0]
    mission_span_s: dict[str, list[float]] = {}
    gcs_pid = os.getpid()
    idle: dict[str, object] = {}
    while thread.is_alive():
        time.sleep(0.25)
        pids = {c.name: c.pid for c in station.supervisor.children}
        pids["gcs"] = gcs_pid
        if idle_s > 0 and not idle and station.phase == "mission":
            idle = hold_and_measure_idle(pids, idle_s, len(scenario.vehicles))
        if gdb_labels and gdb_thread is None and station.phase == "takeoff":
            first_agent = min((n for n in pids if n.startswith("agent_")), default=None)
            if first_agent is not None:
                ref_pid = pids[first_agent]

                def label(pid: int = ref_pid) -> None:
                    nonlocal reference
                    reference = (pid, label_threads_gdb(pid))

                gdb_thread = threading.Thread(target=label, daemon=True)  # sampling goes on while gdb reads
                gdb_thread.start()
        if station.phase == "mission":
            for name, pid in pids.items():
                cpu = cpu_seconds(pid)
                if cpu is None:
                    continue
                start_cpu.setdefault(name, cpu)
                last_cpu[name] = cpu
                peak_rss[name] = max(peak_rss.get(name, 0.0), rss_mb(pid) or 0.0)
                if name.startswith("agent_"):
                    window = thread_windows.setdefault(name, ThreadCpuWindow(pid))
                    window.sample()
                    mission_span_s.setdefault(name, [station.mission_t_s, 0.0])[1] = station.mission_t_s
                    pss = pss_mb(pid)
                    if pss is not None:
                        pss_samples.setdefault(name, []).append(pss)
            if not mission_wall[0]:
                mission_wall[0] = time.monotonic()
            mission_wall[1] = time.monotonic()
    thread.join()
    wall_s = max(mission_wall[1] - mission_wall[0], 1e-9)
    cpu_pct = {name: 100.0 * (last_cpu[name] - start_cpu[name]) / wall_s for name in last_cpu}
    spans = sorted(span[1] - span[0] for span in mission_span_s.values())
    real_time_factor = spans[len(spans) // 2] / wall_s if spans else float("nan")
    if gdb_thread is not None:
        gdb_thread.join(timeout=60.0)
    rates, overruns = [], []
    rate_by_agent: dict[str, float] = {}
    for log in sorted(out_dir.glob("agent_*.log")):
        match = _RATE_RE.search(log.read_text(errors="replace"))
        if match and match.group(2) != "nan":
            rates.append(float(match.group(2)))
            overruns.append(int(match.group(3)))
            rate_by_agent[log.stem] = float(match.group(2))
    # Steps inside each agent's window: its achieved rate [Hz of mission time] times the mission time the window
    # spanned (under the paced clock mission time runs at whatever factor the host gives, not at ``speed``).
    steps = {name: rate_by_agent.get(name, 0.0) * (mission_span_s[name][1] - mission_span_s[name][0])
             for name in thread_windows}
    tick_tables = [per_tick_ms(window.cpu_by_group(), steps[name])
                   for name, window in thread_windows.items() if steps[name] > 0]
    tick_by_thread = median_table(t for t in tick_tables if t)
    wakeups_by_thread = median_table(per_tick(window.wakeups_by_group(), steps[name])
                                     for name, window in thread_windows.items() if steps[name] > 0)
    process_tick = [1000.0 * (last_cpu[name] - start_cpu[name]) / steps[name] for name in thread_windows
                    if steps[name] > 0 and name in last_cpu]  # cross-check: includes threads that ended in between
    reference_tick: dict[str, float] = {}
    reference_name = ""
    if reference is not None:
        ref_pid, ref_labels = reference
        for name, window in thread_windows.items():
            if window.pid == ref_pid:
                reference_name = name
                reference_tick = per_tick_ms(window.cpu_by_group(ref_labels), steps[name])
    agent_pss = [statistics.median(v) for k, v in pss_samples.items() if v]
    sim_log = (out_dir / "sim.log").read_text(errors="replace") if (out_dir / "sim.log").exists() else ""
    cam_log = (out_dir / "cameras.log").read_text(errors="replace") if (out_dir / "cameras.log").exists() else ""
    age = _AGE_RE.search(sim_log)
    frames = _FRAMES_RE.search(cam_log) or _FRAMES_RE.search(sim_log)
    metrics_path = out_dir / "metrics.json"
    summary = json.loads(metrics_path.read_text())["summary"] if metrics_path.exists() else {}
    agent_cpu = [v for k, v in cpu_pct.items() if k.startswith("agent_")]
    agent_rss = [v for k, v in peak_rss.items() if k.startswith("agent_")]
    return {
        **idle,
        "speed": speed,
        "vehicles": len(scenario.vehicles),
        "exit_code": result.get("code"),
        "wall_s": time.monotonic() - wall_start,
        "clock": clock,
        "real_time_factor": real_time_factor,
        "nominal_rate_hz": scenario.control_rate_hz,
        "rate_min_hz": min(rates) if rates else float("nan"),
        "rate_median_hz": statistics.median(rates) if rates else float("nan"),
        "overruns_median": statistics.median(overruns) if overruns else float("nan"),
        "camera_hz": float(frames.group(1)) if frames else float("nan"),
        "camera_nominal_hz": float(frames.group(2)) if frames else float("nan"),
        "setpoint_age_p50_s": float(age.group(1)) if age else float("nan"),
        "setpoint_age_p99_s": float(age.group(2)) if age else float("nan"),
        "agent_cpu_pct_median": statistics.median(agent_cpu) if agent_cpu else float("nan"),
        "agent_cpu_pct_max": max(agent_cpu) if agent_cpu else float("nan"),
        "agent_rss_mb_median": statistics.median(agent_rss) if agent_rss else float("nan"),
        "agent_pss_mb_median": statistics.median(agent_pss) if agent_pss else float("nan"),
        "agent_ms_per_tick": tick_by_thread.get("total", float("nan")),
        "agent_ms_per_tick_by_thread": tick_by_thread,
        "agent_wakeups_per_tick_by_thread": wakeups_by_thread,
        "agent_ms_per_tick_process": statistics.median(process_tick) if process_tick else float("nan"),
        "reference_agent": reference_name,
        "reference_agent_ms_per_tick_by_thread": reference_tick,
        "sim_cpu_pct": cpu_pct.get("sim", float("nan")),
        "sim_rss_mb": peak_rss.get("sim", float("nan")),
        "cameras_cpu_pct": cpu_pct.get("cameras", float("nan")),
        "radio_cpu_pct": cpu_pct.get("radio", float("nan")),
        "gcs_cpu_pct": cpu_pct.get("gcs", float("nan")),
        "total_cpu_pct": sum(cpu_pct.values()),
        "polygon_iou_final": summary.get("polygon_iou_final"),
        "coverage_final": summary.get("coverage_final"),
        "encircle_time_s": summary.get("encircle_time_s"),
        "min_pairwise_distance_m": summary.get("min_pairwise_distance_m"),
    }


def hold_and_measure_idle(pids: dict[str, int], idle_s: float, vehicles: int) -> dict[str, object]:
    """Close the paced clock's gate, measure every process for ``idle_s`` wall seconds, open it again."""
    from bench.agent_idle_cost import LoopbackTraffic, PaceGate, measure_idle  # noqa: PLC0415 - idle runs only
    from mock_autopilot.ports import onboard_port  # noqa: PLC0415

    gate = PaceGate(ZENOH_ENDPOINT, "bench")
    try:
        held_at = gate.close_gate()
        time.sleep(2.0)  # the clock reaches the held tick and the agents answer it
        traffic = LoopbackTraffic(frozenset(onboard_port(BASE_PORT, i, GCS_PORT) for i in range(vehicles)), GCS_PORT,
                                  int(ZENOH_ENDPOINT.rsplit(":", 1)[1]))
        row = measure_idle(pids, idle_s, traffic)
        row["idle_held_at_t_s"] = held_at
        row["idle_agent_ms_per_s"] = row["idle_agent_cpu_ms_per_s"].get("total", float("nan"))  # type: ignore[union-attr]
        row["idle_sim_ms_per_s"] = row["idle_service_cpu_ms_per_s"].get("sim", float("nan"))  # type: ignore[union-attr]
        gate.open_gate()
    finally:
        gate.close()
    return row


def holds(row: dict[str, object]) -> bool:
    """The mission held its speed: it completed, every agent ran at >= 90 % of the nominal control rate, the
    simulator delivered >= 90 % of the nominal camera frames, and mission time ran at >= 90 % of the speed asked
    for (a paced clock keeps every rate by slowing down instead: the real-time factor is what it gives up)."""
    return (row["exit_code"] == 0 and float(row["rate_min_hz"]) >= 0.9 * float(row["nominal_rate_hz"])  # type: ignore[arg-type]
            and float(row["camera_hz"]) >= 0.9 * float(row["camera_nominal_hz"])  # type: ignore[arg-type]
            and float(row["real_time_factor"]) >= 0.9 * float(row["speed"]))  # type: ignore[arg-type]


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="circle")
    p.add_argument("--mode", default="improved")
    p.add_argument("--speeds", default="1,2,4")
    p.add_argument("--duration", type=float, default=30.0)
    p.add_argument("--sizes", default="", help="boundary drones per group to try, ascending (fleet scaling at the first "
                   "speed; one follower layer of the same size); replaces the plain speed runs")
    p.add_argument("--set", action="append", default=[], dest="overrides", metavar="KEY=VALUE",
                   help="override a scenario parameter for every run, e.g. control_rate_hz=10")
    p.add_argument("--gdb-labels", action="store_true", help="split MAVSDK's unnamed threads by their native stacks "
                   "(gdb pauses one agent for about a second during take-off)")
    p.add_argument("--clock", choices=("paced", "free"), default="paced")
    p.add_argument("--idle-s", type=float, default=0.0, help="paced clock: first hold the clock this many wall "
                   "seconds (< 60) and report what each agent costs while nothing moves (bench/agent_idle_cost.py)")
    p.add_argument("--out", type=Path, default=Path("runs/bench-processes"))
    args = p.parse_args()
    common = tuple(args.overrides)
    rows = []
    sizes = [int(s) for s in args.sizes.split(",") if s]
    runs: list[tuple[float, tuple[str, ...]]] = [] if sizes else [(float(s), ()) for s in args.speeds.split(",") if s]
    for size in sizes:
        followers = max(1, size)
        runs.append((float(args.speeds.split(",")[0]), (f"fleet.boundary_per_group={size}",
                                                          f"fleet.follower_layers=[{followers}]")))
    for speed, overrides in runs:
        tag = f"x{speed:g}" + ("-" + "-".join(o.split("=")[1] for o in overrides) if overrides else "")
        row = run_once(args.scenario, common + overrides, speed, args.duration, args.out / tag, args.mode,
                       gdb_labels=args.gdb_labels, clock=args.clock, idle_s=args.idle_s)
        row["holds"] = holds(row)
        rows.append(row)
        print(json.dumps(row), flush=True)
        if sizes and not row["holds"]:
            break  # fleet scaling: sizes go up, the first one that does not hold ends the search
    keys = ["speed", "vehicles", "exit_code", "holds", "real_time_factor", "rate_min_hz", "rate_median_hz", "camera_hz", "setpoint_age_p50_s",
            "setpoint_age_p99_s", "agent_cpu_pct_median", "agent_ms_per_tick", "idle_agent_ms_per_s", "idle_sim_ms_per_s",
            "agent_rss_mb_median",
            "agent_pss_mb_median", "sim_cpu_pct", "sim_rss_mb",
            "cameras_cpu_pct", "radio_cpu_pct", "gcs_cpu_pct", "total_cpu_pct", "polygon_iou_final", "coverage_final",
            "min_pairwise_distance_m"]
    print("| " + " | ".join(keys) + " |")
    print("|" + "---|" * len(keys))
    for row in rows:
        print("| " + " | ".join(_fmt(row.get(k)) for k in keys) + " |")
    return 0


def _fmt(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.3g}"
    return str(value)


if __name__ == "__main__":
    sys.exit(main())
