"""Where an agent process's CPU goes, per control tick, read from /proc (and its memory as PSS).

Wall-clock timing on a shared 2-core machine says more about the neighbours' load than about the agent, so every
figure here is CPU time the kernel charged to the agent's threads (``utime + stime`` of
``/proc/<pid>/task/<tid>/stat``), taken over the MISSION phase and divided by the control steps the agent logged.
Threads are grouped by what they are:

* ``main``: the Python main thread (asyncio loop, onboard core, perception, Zenoh ``put`` from Python);
* ``zenoh <pool>``: Zenoh's tokio runtimes (``rx``, ``tx``, ``net``, ``acc``, ``app``; see ``ZENOH_RUNTIME``) and its
  shared-memory watchdog threads, which Zenoh names;
* the rest inherit the name ``python``: MAVSDK's C++ threads (asio I/O, user callbacks, HTTP loader), the asyncio
  default executor's worker threads, OpenBLAS's idle pool. ``label_threads_gdb`` tells them apart from their native
  stacks (``--gdb``); gdb pauses the process it reads, so only one agent (the reference) is labelled, during
  take-off. On a loaded host the pause can outlast the agent's 2 s autopilot-silence rule and end that agent's
  flight (exit code 3), so labelling is asked for, not the default.

Memory is PSS (``/proc/<pid>/smaps_rollup``): agents share the interpreter, numpy, OpenCV, MAVSDK and Zenoh pages,
and RSS would count those once per agent.

Usage (one mission, per-thread table)::

    python bench/agent_tick_cost.py --duration 30                       # circle, 13 vehicles, 20 Hz, paced clock
    python bench/agent_tick_cost.py --duration 30 --clock free          # the agents' own wall-clock loop
    python bench/agent_tick_cost.py --duration 30 --set control_rate_hz=10
    python bench/agent_tick_cost.py --duration 20 --pin-agents-after-s 7    # each agent kept on one CPU
    python bench/agent_tick_cost.py --mavsdk-streams                    # MAVSDK's cost per telemetry profile

``--mavsdk-streams`` isolates MAVSDK: one mock PX4 (a child process) streaming the mock's reduced profile or PX4's
own onboard rates, one ``MavsdkAutopilotLink`` in this process (no Zenoh, no control loop), with and without the
link's rate requests; CPU and wake-ups of this process's threads per second.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import threading
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

_CLK_TCK = os.sysconf("SC_CLK_TCK")
_ZENOH_POOLS = ("rx", "tx", "net", "acc", "app")
_GDB_THREAD_RE = re.compile(r'^Thread \d+ \(Thread 0x[0-9a-f]+ \(LWP (\d+)\) "([^"]*)"\):')
# Native-stack markers, most specific first: the first that occurs in a thread's backtrace names it.
_STACK_LABELS: tuple[tuple[str, str], ...] = (
    ("process_user_callbacks_thread", "mavsdk callbacks"),
    ("HttpLoader", "mavsdk http loader"),
    ("MavsdkImpl", "mavsdk io (asio)"),
    ("asio::", "mavsdk io (asio)"),
    ("libcmavsdk", "mavsdk other"),
    ("blas_thread_server", "openblas (idle pool)"),
    ("SimpleQueue_get", "asyncio executor"),
    ("PyEval", "python thread"),
)


@dataclass(frozen=True)
class ThreadSample:
    """One thread's kernel name (``comm``), cumulative CPU time [s] and cumulative wake-ups at one read.

    Wake-ups are the kernel's ``voluntary_ctxt_switches``: how often the thread went to sleep (on a timer, a
    socket, a lock or the GIL) and had to be woken again, the fixed cost that small messages multiply.
    """

    name: str
    cpu_s: float
    wakeups: int = 0


def thread_samples(pid: int) -> dict[int, ThreadSample]:
    """Every live thread of ``pid``: tid -> (name, cumulative utime + stime [s]); empty if the process is gone."""
    samples: dict[int, ThreadSample] = {}
    try:
        tids = os.listdir(f"/proc/{pid}/task")
    except OSError:
        return samples
    for tid in tids:
        try:
            stat = Path(f"/proc/{pid}/task/{tid}/stat").read_text()
        except OSError:
            continue
        name = stat[stat.index("(") + 1: stat.rindex(")")]
        fields = stat.rsplit(")", 1)[1].split()
        samples[int(tid)] = ThreadSample(name, (int(fields[11]) + int(fields[12])) / _CLK_TCK, _wakeups(pid, tid))
    return samples


def _wakeups(pid: int, tid: str) -> int:
    try:
        for line in Path(f"/proc/{pid}/task/{tid}/status").read_text().splitlines():
            if line.startswith("voluntary_ctxt_switches:"):
                return int(line.split()[1])
    except OSError:
        pass
    return 0


def pss_mb(pid: int) -> float | None:
    """Proportional set size [MiB]: this process's private pages plus its share of every shared page."""
    try:
        for line in Path(f"/proc/{pid}/smaps_rollup").read_text().splitlines():
            if line.startswith("Pss:"):
                return int(line.split()[1]) / 1024.0
    except OSError:
        return None
    return None


def thread_group(pid: int, tid: int, name: str, labels: Mapping[int, str] | None = None) -> str:
    """The group a thread's CPU is reported under (see the module docstring)."""
    if tid == pid:
        return "main"
    pool = name.split("-")[0]
    if pool in _ZENOH_POOLS and name[len(pool) + 1:].isdigit():
        return f"zenoh {pool}"
    if name.startswith("Watchdog"):
        return "zenoh shm watchdog"
    if labels is not None and tid in labels:
        return labels[tid]
    return "unnamed: mavsdk + executor"


@dataclass
class ThreadCpuWindow:
    """Per-thread CPU of one process between a first and a last read (threads born in between count from 0)."""

    pid: int
    first: dict[int, ThreadSample] = field(default_factory=dict)
    last: dict[int, ThreadSample] = field(default_factory=dict)
    started: bool = False
    first_wall_s: float = 0.0
    last_wall_s: float = 0.0

    def sample(self) -> None:
        """Read the threads now; the first call opens the window, every call moves its end."""
        now = thread_samples(self.pid)
        if not now:
            return
        wall_s = time.monotonic()
        if not self.started:
            self.first, self.started, self.first_wall_s = dict(now), True, wall_s
        self.last.update(now)
        self.last_wall_s = wall_s

    @property
    def wall_s(self) -> float:
        """Wall time between the first and the last read [s]."""
        return self.last_wall_s - self.first_wall_s

    def cpu_by_tid(self) -> dict[int, tuple[str, float]]:
        """tid -> (name, CPU [s] spent inside the window)."""
        return {tid: (s.name, s.cpu_s - (self.first[tid].cpu_s if tid in self.first else 0.0))
                for tid, s in self.last.items()}

    def wakeups_by_group(self, labels: Mapping[int, str] | None = None) -> dict[str, float]:
        """Group name -> wake-ups inside the window."""
        groups: dict[str, float] = {}
        for tid, s in self.last.items():
            group = thread_group(self.pid, tid, s.name, labels)
            groups[group] = groups.get(group, 0.0) + s.wakeups - (self.first[tid].wakeups if tid in self.first else 0)
        return groups

    def cpu_by_group(self, labels: Mapping[int, str] | None = None) -> dict[str, float]:
        """Group name -> CPU [s] inside the window."""
        groups: dict[str, float] = {}
        for tid, (name, cpu_s) in self.cpu_by_tid().items():
            group = thread_group(self.pid, tid, name, labels)
            groups[group] = groups.get(group, 0.0) + cpu_s
        return groups


def label_threads_gdb(pid: int, timeout_s: float = 60.0) -> dict[int, str]:
    """tid -> label from each thread's native backtrace (gdb attaches, pausing the process for about a second).

    Only for the unnamed threads; returns {} when gdb is missing or fails. Call it outside the measured window.
    """
    try:
        out = subprocess.run(["gdb", "-p", str(pid), "-batch", "-nx", "-ex", "thread apply all bt 14"],
                             capture_output=True, text=True, timeout=timeout_s).stdout
    except (OSError, subprocess.TimeoutExpired):
        return {}
    labels: dict[int, str] = {}
    current: tuple[int, str] | None = None
    frames: list[str] = []

    def finish() -> None:
        if current is not None and current[1] == "python" and current[0] != pid:
            text = "\n".join(frames)
            labels[current[0]] = next((label for marker, label in _STACK_LABELS if marker in text), "unnamed other")

    for line in out.splitlines():
        match = _GDB_THREAD_RE.match(line)
        if match:
            finish()
            current, frames = (int(match.group(1)), match.group(2)), []
        elif line.startswith("#"):
            frames.append(line)
    finish()
    return labels


def per_tick(by_group: Mapping[str, float], control_steps: float, scale: float = 1.0) -> dict[str, float]:
    """Group -> amount per control step times ``scale``, plus ``total``."""
    if control_steps <= 0:
        return {}
    table = {group: scale * value / control_steps for group, value in by_group.items()}
    table["total"] = sum(table.values())
    return table


def per_tick_ms(cpu_by_group: Mapping[str, float], control_steps: float) -> dict[str, float]:
    """Group -> CPU [ms] per control step, plus ``total``.

    ``control_steps`` are the steps inside the window: the agent's achieved rate times the window's length (its own
    step count covers its MISSION phase, which starts and ends a little apart from the window).
    """
    return per_tick(cpu_by_group, control_steps, 1000.0)


def median_table(tables: Iterable[Mapping[str, float]]) -> dict[str, float]:
    """Per-key median over several agents' tables (a key missing in one agent counts as 0 there)."""
    rows = list(tables)
    keys = sorted({k for row in rows for k in row})
    out: dict[str, float] = {}
    for key in keys:
        values = sorted(row.get(key, 0.0) for row in rows)
        mid = len(values) // 2
        out[key] = values[mid] if len(values) % 2 else 0.5 * (values[mid - 1] + values[mid])
    return out


def mavsdk_stream_cost(profile: str, request_rates: bool, seconds: float = 15.0, port: int = 27500) -> dict[str, float]:
    """CPU [ms/s] and wake-ups [1/s] of this process's threads while one MAVSDK link listens to one mock PX4."""
    import asyncio  # noqa: PLC0415 - only this measurement needs them
    import math  # noqa: PLC0415

    from vehicle_agents.autopilot_link_mavsdk import TELEMETRY_RATES_HZ, MavsdkAutopilotLink  # noqa: PLC0415

    fleet = subprocess.Popen([sys.executable, "-m", "mock_autopilot", "--vehicles", "1", "--base-port", str(port),
                              "--gcs-port", str(port + 5), "--stream-rates", profile],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    async def measure() -> dict[str, float]:
        link = MavsdkAutopilotLink(f"udpin://0.0.0.0:{port}", TELEMETRY_RATES_HZ if request_rates else None)
        try:
            await link.connect(30.0)
            await asyncio.sleep(3.0)
            window = ThreadCpuWindow(os.getpid())
            window.sample()
            await asyncio.sleep(seconds)
            window.sample()
            heard = math.isfinite(link.telemetry.position_ned_m[0])
        finally:
            await link.close()
        cpu = sum(cpu_s for name, cpu_s in window.cpu_by_tid().values())
        wakeups = sum(window.wakeups_by_group().values())
        return {"cpu_ms_per_s": 1000.0 * cpu / window.wall_s, "wakeups_per_s": wakeups / window.wall_s,
                "heard": float(heard)}

    try:
        return asyncio.run(measure())
    finally:
        fleet.terminate()
        fleet.wait(10)


def agent_pids() -> list[int]:
    """The pids of this machine's agent processes (``python -m vehicle_agents``), by their command lines."""
    pids = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                argv = Path(f"/proc/{entry}/cmdline").read_bytes().split(b"\0")
            except OSError:
                continue
            if b"vehicle_agents" in argv:
                pids.append(int(entry))
    return sorted(pids)


def pin_agents_later(delay_s: float) -> None:
    """After ``delay_s``, pin each agent's threads to one CPU (agent k to the k-th CPU, modulo their number)."""
    time.sleep(delay_s)
    cpus = sorted(os.sched_getaffinity(0))
    pinned = 0
    for k, pid in enumerate(agent_pids()):
        try:
            for tid in os.listdir(f"/proc/{pid}/task"):
                os.sched_setaffinity(int(tid), {cpus[k % len(cpus)]})
            pinned += 1
        except OSError:
            continue
    print(f"pinned {pinned} agent processes over CPUs {cpus}", file=sys.stderr, flush=True)


def main() -> int:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="circle")
    p.add_argument("--mode", default="improved")
    p.add_argument("--speed", type=float, default=1.0)
    p.add_argument("--duration", type=float, default=30.0)
    p.add_argument("--set", action="append", default=[], dest="overrides", metavar="KEY=VALUE")
    p.add_argument("--clock", choices=("paced", "free"), default="paced")
    p.add_argument("--gdb", action="store_true", help="label MAVSDK's unnamed threads from one agent's native stacks "
                   "(gdb pauses that agent during take-off)")
    p.add_argument("--out", type=Path, default=Path("runs/bench-agent-tick"))
    p.add_argument("--mavsdk-streams", action="store_true", help="MAVSDK's own cost per telemetry profile instead")
    p.add_argument("--repeat", type=int, default=2, help="with --mavsdk-streams: runs per case")
    p.add_argument("--pin-agents-after-s", type=float, default=None, metavar="S",
                   help="S wall seconds after the start, pin every agent process (all its threads) to one CPU, "
                        "alternating over the CPUs: whether keeping an agent on one core's caches makes it cheaper")
    args = p.parse_args()
    if args.mavsdk_streams:
        print("| mock stream profile | link requests rates | MAVSDK process CPU ms/s | wake-ups /s |")
        print("|---|---|---|---|")
        for profile in ("reduced", "px4"):
            for request in (False, True):
                runs = [mavsdk_stream_cost(profile, request) for _ in range(args.repeat)]
                cpu = sorted(r["cpu_ms_per_s"] for r in runs)
                wake = sorted(r["wakeups_per_s"] for r in runs)
                print(f"| {profile} | {'yes' if request else 'no'} | {' / '.join(f'{c:.1f}' for c in cpu)} | "
                      f"{' / '.join(f'{w:.0f}' for w in wake)} |", flush=True)
        return 0
    from bench.mission_processes import run_once  # noqa: PLC0415 - heavy (the ground station) and CLI-only
    if args.pin_agents_after_s is not None:
        threading.Thread(target=pin_agents_later, args=(args.pin_agents_after_s,), daemon=True).start()
    row = run_once(args.scenario, tuple(args.overrides), args.speed, args.duration, args.out, args.mode,
                   gdb_labels=args.gdb, clock=args.clock)
    print(json.dumps(row), flush=True)
    for title, key in (("median over agents", "agent_ms_per_tick_by_thread"),
                       ("reference agent, gdb labels", "reference_agent_ms_per_tick_by_thread")):
        table = row.get(key) or {}
        print(f"| thread group | ms CPU per agent per tick ({title}) |")
        print("|---|---|")
        for group, ms in sorted(table.items(), key=lambda kv: (kv[0] == "total", -kv[1])):
            print(f"| {group} | {ms:.3f} |")
    wakeups = row.get("agent_wakeups_per_tick_by_thread") or {}
    print("wake-ups per agent per tick (median): " + ", ".join(f"{g} {v:.1f}" for g, v in sorted(wakeups.items())))
    print(f"PSS per agent (median): {row.get('agent_pss_mb_median', float('nan')):.1f} MiB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
