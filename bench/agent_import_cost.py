"""What an agent process costs before it flies: the memory (PSS, private) and time of importing what
``python -m vehicle_agents`` imports, in fresh interpreters, per checkout of the code.

Every drone runs one agent process, so whatever its imports bring is paid once per vehicle (208 times in ``large``).
Each sample starts ``--agents`` fresh interpreters one after the other from a checkout's directory (so that
checkout's packages come first on ``sys.path``); each imports what the agent's ``main`` imports before flying
(``vehicle_agents.__main__``, the Zenoh swarm link, the simulation-clock link and the autopilot link of ``--link``),
reports how long the imports took and how many modules it holds, and waits. Once all of them are up their memory is
read from ``/proc/<pid>/smaps_rollup``: PSS, which shares each shared page among the processes mapping it (several
agents share the interpreter, numpy, OpenCV, MAVSDK and Zenoh pages, as a fleet's agents do), and private pages,
which no sharing makes smaller. The interpreters start one at a time so the import times do not compete with each
other; checkouts alternate sample by sample so a change of the host's load falls on both, after one unreported
interpreter per checkout that warms the page cache and writes the bytecode caches.

This is the import cost only: a flying agent also holds MAVSDK's and Zenoh's sessions and buffers
(``bench/agent_tick_cost.py`` reads PSS in flight). No sockets are opened.

Usage::

    python bench/agent_import_cost.py --checkout /work/main --checkout . --rounds 3
    python bench/agent_import_cost.py --checkout . --link pymavlink
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

AGENT_IMPORTS: dict[str, tuple[str, ...]] = {
    "mavsdk": ("vehicle_agents.__main__", "vehicle_agents.swarm_link_zenoh", "vehicle_agents.sim_clock_link",
               "vehicle_agents.autopilot_link_mavsdk"),
    "pymavlink": ("vehicle_agents.__main__", "vehicle_agents.swarm_link_zenoh", "vehicle_agents.sim_clock_link",
                  "vehicle_agents.autopilot_link_pymavlink"),
}
"""What ``vehicle_agents.__main__.main`` imports before its agent flies, per ``--link``."""

CHILD = """
import importlib, json, sys, time
start_s = time.perf_counter()
for name in sys.argv[1:]:
    importlib.import_module(name)
import_s = time.perf_counter() - start_s
import comms
print(json.dumps({"import_s": import_s, "modules": len(sys.modules), "comms": comms.__file__,
                  "pymavlink": any(m.split(".")[0] == "pymavlink" for m in sys.modules)}), flush=True)
sys.stdin.read()
"""
"""A fresh interpreter's part: import, report, then hold its memory until the parent closes its stdin."""

SMAPS_FIELDS_KIB = ("Rss", "Pss", "Private_Clean", "Private_Dirty")


@dataclass(frozen=True)
class AgentSample:
    """One fresh interpreter after an agent's imports."""

    import_ms: float
    start_ms: float
    """From starting the interpreter to its report: the interpreter's own start-up plus the imports."""
    modules: int
    loads_pymavlink: bool
    pss_mib: float
    private_mib: float
    rss_mib: float


def smaps_rollup_kib(pid: int) -> dict[str, int]:
    """The :data:`SMAPS_FIELDS_KIB` lines of ``/proc/<pid>/smaps_rollup`` [KiB]."""
    fields: dict[str, int] = {}
    for line in Path(f"/proc/{pid}/smaps_rollup").read_text().splitlines():
        key, _, rest = line.partition(":")
        if key in SMAPS_FIELDS_KIB:
            fields[key] = int(rest.split()[0])
    return fields


def sample_checkout(checkout: Path, imports: Sequence[str], agents: int) -> list[AgentSample]:
    """Start ``agents`` interpreters in ``checkout`` one after the other, read each once all are up, end them."""
    children: list[tuple[subprocess.Popen[str], Mapping[str, object], float]] = []
    try:
        for _ in range(agents):
            started_s = time.perf_counter()
            child = subprocess.Popen([sys.executable, "-c", CHILD, *imports], cwd=checkout, text=True,
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE)
            assert child.stdout is not None
            line = child.stdout.readline()
            start_ms = (time.perf_counter() - started_s) * 1000.0
            if not line:
                raise RuntimeError(f"{checkout}: the agent's imports failed (exit code {child.wait()})")
            report = json.loads(line)
            if not Path(str(report["comms"])).is_relative_to(checkout):
                raise RuntimeError(f"{checkout}: imported comms from {report['comms']}, not from this checkout")
            children.append((child, report, start_ms))
        samples = []
        for child, report, start_ms in children:
            kib = smaps_rollup_kib(child.pid)
            samples.append(AgentSample(
                import_ms=float(report["import_s"]) * 1000.0, start_ms=start_ms, modules=int(report["modules"]),
                loads_pymavlink=bool(report["pymavlink"]), pss_mib=kib["Pss"] / 1024.0,
                private_mib=(kib["Private_Clean"] + kib["Private_Dirty"]) / 1024.0, rss_mib=kib["Rss"] / 1024.0))
        return samples
    finally:
        for child, _, _ in children:
            assert child.stdin is not None
            child.stdin.close()
            child.wait(timeout=30)


def git_head(checkout: Path) -> str:
    """The checkout's commit (short), for the record."""
    out = subprocess.run(["git", "-C", str(checkout), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    return out.stdout.strip() or "?"


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--checkout", action="append", type=Path, required=True,
                   help="a directory holding the project's packages; repeat to alternate several")
    p.add_argument("--rounds", type=int, default=3, help="samples per checkout, alternated")
    p.add_argument("--agents", type=int, default=4, help="interpreters alive together per sample (they share pages)")
    p.add_argument("--link", choices=sorted(AGENT_IMPORTS), default="mavsdk", help="the agent's --link")
    args = p.parse_args()
    checkouts = [c.resolve() for c in args.checkout]
    imports = AGENT_IMPORTS[args.link]
    print("| checkout | commit | round | import ms (median) | start-up ms (median) | modules | pymavlink loaded | PSS MiB (median) | "
          "private MiB (median) | RSS MiB (median) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for checkout in checkouts:
        sample_checkout(checkout, imports, 1)
    by_checkout: dict[Path, list[AgentSample]] = {c: [] for c in checkouts}
    for round_number in range(1, args.rounds + 1):
        for checkout in checkouts:
            samples = sample_checkout(checkout, imports, args.agents)
            by_checkout[checkout].extend(samples)
            print(f"| {checkout} | {git_head(checkout)} | {round_number} | "
                  f"{statistics.median(s.import_ms for s in samples):.0f} | "
                  f"{statistics.median(s.start_ms for s in samples):.0f} | "
                  f"{statistics.median(s.modules for s in samples):.0f} | "
                  f"{'yes' if any(s.loads_pymavlink for s in samples) else 'no'} | "
                  f"{statistics.median(s.pss_mib for s in samples):.1f} | "
                  f"{statistics.median(s.private_mib for s in samples):.1f} | "
                  f"{statistics.median(s.rss_mib for s in samples):.1f} |", flush=True)
    print()
    for checkout, samples in by_checkout.items():
        print(f"{checkout}: {len(samples)} interpreters, import ms median "
              f"{statistics.median(s.import_ms for s in samples):.0f} (min {min(s.import_ms for s in samples):.0f}), start-up ms median "
              f"{statistics.median(s.start_ms for s in samples):.0f}, "
              f"PSS MiB median {statistics.median(s.pss_mib for s in samples):.1f}, private MiB median "
              f"{statistics.median(s.private_mib for s in samples):.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
