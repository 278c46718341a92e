"""What a processes-engine mission costs while its paced clock stands still: the idle cost per agent and per vehicle.

A paced tick is owed by every agent; an agent starved of CPU holds the clock, and while it waits every other
process keeps doing what runs on the wall clock: MAVSDK re-sends the newest offboard setpoint (20 Hz) and sends its
heartbeat (1 Hz), the mock PX4s send theirs (1 Hz on each link), Zenoh keeps its links alive, the fleet repeats the
clock tick (2 Hz) and the ground station its order (2 Hz), and each agent polls its clock wait. On a host that
cannot give a large fleet what one tick costs, that floor is what decides whether the clock moves at all.

This bench flies a mission (``bench.mission_processes.run_once``), and once every vehicle is in its MISSION phase it
closes the clock's gate from outside: it joins the mission's Zenoh hub as one more pace participant
(:class:`PaceGate`), acknowledges the newest clock tick once and then no more, so the fleet stands at the next tick
(the agents computed it and wait for the one after). For ``--idle-s`` seconds (< 60, the ground station's
clock-stall limit) it reads every process's threads from /proc (CPU per wall second, wake-ups per wall second,
split by thread as ``bench/agent_tick_cost.py`` does) and counts the datagrams on the loopback interface by MAVLink
message id and direction (agents' MAVSDK -> fleet, fleet -> agents, fleet -> ground station) and the Zenoh TCP
segments, then says it leaves: the clock moves on and the mission ends normally. The run is given an agent timeout
longer than the window, so the gate is never left behind.

Run it in its own network namespace (it opens ports and a packet socket on loopback)::

    unshare -n bash -c 'ip link set lo up; exec .venv/bin/python bench/agent_idle_cost.py --idle-s 30'
    ... bench/agent_idle_cost.py --scenario large --set fleet.boundary_per_group=3 --set 'fleet.follower_layers=[3]'
"""

from __future__ import annotations

import socket
import struct
import sys
import threading
import time
from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.agent_tick_cost import ThreadCpuWindow, median_table, pss_mb  # noqa: E402
from comms.keys import MissionKeys  # noqa: E402
from comms.messages import PaceAck, SimClockTick, decode, encode  # noqa: E402
from comms.zenoh_session import ZenohConfig, ZenohSession  # noqa: E402

GATE_PARTICIPANT = "idle-gate"
_ETH_P_ALL = 0x0003
_PACKET_OUTGOING = 4
_MAVLINK2_STX = 0xFD
_MAVLINK2_HEADER = 10
_MAVLINK2_CRC = 2
_MAVLINK2_SIGNATURE = 13
_COMMAND_LONG = 76
_COMMAND_FIELD = 28
"""Offset of COMMAND_LONG's ``command`` in its payload (seven float params first)."""


class PaceGate:
    """Holds a paced mission's clock from outside: a pace participant that acknowledges one tick and then waits."""

    def __init__(self, endpoint: str, mission: str) -> None:
        self.keys = MissionKeys(mission)
        self.session = ZenohSession(ZenohConfig.client(endpoint))
        self._ticks = self.session.subscribe(self.keys.clock)
        self._newest_t_s: float | None = None

    def newest_tick_s(self, wait_s: float = 5.0) -> float | None:
        """Mission time of the newest clock tick heard (waiting up to ``wait_s`` for the first)."""
        deadline = time.monotonic() + wait_s
        while True:
            for item in self._ticks.drain():
                tick = decode(SimClockTick, item.payload)
                if tick is not None and (self._newest_t_s is None or tick.t_s > self._newest_t_s):
                    self._newest_t_s = tick.t_s
            if self._newest_t_s is not None or time.monotonic() >= deadline:
                return self._newest_t_s
            self._ticks.wait(0.1)

    def close_gate(self) -> float | None:
        """Acknowledge the newest tick: the clock then stands at the one after it. Returns that tick's time."""
        t_s = self.newest_tick_s()
        if t_s is not None:
            self.session.put(self.keys.pace(GATE_PARTICIPANT), encode(PaceAck(participant=GATE_PARTICIPANT, t_s=t_s)))
        return t_s

    def open_gate(self) -> None:
        """Say this participant leaves: the clock moves on without it."""
        t_s = self.newest_tick_s(wait_s=0.5) or 0.0
        self.session.put(self.keys.pace(GATE_PARTICIPANT),
                         encode(PaceAck(participant=GATE_PARTICIPANT, t_s=t_s + 1e-3, leaving=True)))

    def close(self) -> None:
        self.session.close()


@dataclass
class LoopbackTraffic:
    """Datagrams and TCP segments sent on loopback, counted from a packet socket (each counted once, outgoing)."""

    agent_ports: frozenset[int]
    gcs_port: int
    zenoh_port: int
    mavlink: Counter[tuple[str, int]] = field(default_factory=Counter)
    """(direction, MAVLink message id) -> frames."""
    commands: Counter[tuple[str, int, float]] = field(default_factory=Counter)
    """(direction, MAV_CMD of a COMMAND_LONG, its param1) -> frames."""
    datagrams: Counter[str] = field(default_factory=Counter)
    tcp_segments: Counter[str] = field(default_factory=Counter)
    _stop: threading.Event = field(default_factory=threading.Event)
    _thread: threading.Thread | None = None
    wall_s: float = 0.0

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="loopback-count", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=5.0)

    def _run(self) -> None:
        try:
            sock = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(_ETH_P_ALL))
            sock.bind(("lo", 0))
        except OSError as exc:
            print(f"loopback count unavailable: {exc}", file=sys.stderr)
            return
        sock.settimeout(0.2)
        started = time.monotonic()
        with sock:
            while not self._stop.is_set():
                try:
                    frame, address = sock.recvfrom(65535)
                except TimeoutError:
                    continue
                if address[2] == _PACKET_OUTGOING:
                    self._count(frame)
        self.wall_s = time.monotonic() - started

    def _count(self, frame: bytes) -> None:
        if len(frame) < 14 + 20 or frame[12:14] != b"\x08\x00":
            return
        ip = frame[14:]
        header_len = (ip[0] & 0x0F) * 4
        protocol = ip[9]
        body = ip[header_len:]
        if len(body) < 8:
            return
        src, dst = struct.unpack_from("!HH", body)
        if protocol == socket.IPPROTO_TCP and self.zenoh_port in (src, dst):
            self.tcp_segments["to hub" if dst == self.zenoh_port else "from hub"] += 1
            return
        if protocol == socket.IPPROTO_TCP:
            self.tcp_segments["peer to peer"] += 1
            return
        if protocol != socket.IPPROTO_UDP:
            return
        if src in self.agent_ports:
            direction = "agent -> fleet"
        elif dst in self.agent_ports:
            direction = "fleet -> agent"
        elif dst == self.gcs_port:
            direction = "fleet -> gcs"
        elif src == self.gcs_port:
            direction = "gcs -> fleet"
        else:
            return
        self.datagrams[direction] += 1
        self._count_frames(direction, body[8:])

    def _count_frames(self, direction: str, payload: bytes) -> None:
        i = 0
        while i + _MAVLINK2_HEADER <= len(payload) and payload[i] == _MAVLINK2_STX:
            length, incompat = payload[i + 1], payload[i + 2]
            msg_id = payload[i + 7] | payload[i + 8] << 8 | payload[i + 9] << 16
            self.mavlink[(direction, msg_id)] += 1
            if msg_id == _COMMAND_LONG and length >= _COMMAND_FIELD + 2:
                at = i + _MAVLINK2_HEADER
                param1 = struct.unpack_from("<f", payload, at)[0]
                command = payload[at + _COMMAND_FIELD] | payload[at + _COMMAND_FIELD + 1] << 8
                self.commands[(direction, command, param1)] += 1
            i += _MAVLINK2_HEADER + length + _MAVLINK2_CRC + (_MAVLINK2_SIGNATURE if incompat & 1 else 0)

    def rates(self) -> dict[str, float]:
        """Name -> per wall second, for the report."""
        wall_s = max(self.wall_s, 1e-9)
        from pymavlink.dialects.v20 import common as mavlink  # noqa: PLC0415 - names only for the report

        out: dict[str, float] = {}
        for (direction, msg_id), n in sorted(self.mavlink.items()):
            name = mavlink.mavlink_map[msg_id].msgname if msg_id in mavlink.mavlink_map else f"id {msg_id}"
            out[f"mavlink {direction} {name}"] = n / wall_s
        commands = {v: k for k, v in vars(mavlink).items() if k.startswith("MAV_CMD_") and isinstance(v, int)}
        for (direction, command, param1), n in sorted(self.commands.items()):
            out[f"mavlink {direction} COMMAND_LONG {commands.get(command, command)} ({param1:g})"] = n / wall_s
        for direction, n in sorted(self.datagrams.items()):
            out[f"datagrams {direction}"] = n / wall_s
        for direction, n in sorted(self.tcp_segments.items()):
            out[f"zenoh tcp segments {direction}"] = n / wall_s
        return out


def per_second(window: ThreadCpuWindow, labels: Mapping[int, str] | None = None) -> tuple[dict[str, float], dict[str, float]]:
    """(thread group -> CPU ms per wall second, thread group -> wake-ups per wall second), with ``total``."""
    wall_s = max(window.wall_s, 1e-9)
    cpu = {group: 1000.0 * cpu_s / wall_s for group, cpu_s in window.cpu_by_group(labels).items()}
    cpu["total"] = sum(cpu.values())
    wakeups = {group: n / wall_s for group, n in window.wakeups_by_group(labels).items()}
    wakeups["total"] = sum(wakeups.values())
    return cpu, wakeups


def measure_idle(pids: Mapping[str, int], seconds: float, traffic: LoopbackTraffic | None) -> dict[str, object]:
    """Per-thread CPU and wake-ups of every process over ``seconds`` of wall time (the gate already closed)."""
    windows = {name: ThreadCpuWindow(pid) for name, pid in pids.items()}
    if traffic is not None:
        traffic.start()
    for window in windows.values():
        window.sample()
    time.sleep(seconds)
    for window in windows.values():
        window.sample()
    if traffic is not None:
        traffic.stop()
    tables = {name: per_second(window) for name, window in windows.items() if window.wall_s > 0}
    agents = [name for name in tables if name.startswith("agent_")]
    agent_pss = sorted(p for p in (pss_mb(pids[name]) for name in agents) if p is not None)
    services = {name: table[0]["total"] for name, table in tables.items() if not name.startswith("agent_")}
    return {
        "idle_wall_s": seconds,
        "idle_agents": len(agents),
        "idle_agent_cpu_ms_per_s": median_table(tables[name][0] for name in agents),
        "idle_agent_wakeups_per_s": median_table(tables[name][1] for name in agents),
        "idle_agents_total_cpu_pct": sum(tables[name][0]["total"] for name in agents) / 10.0,
        "idle_service_cpu_ms_per_s": services,
        "idle_service_threads_ms_per_s": {name: tables[name][0] for name in services},
        "idle_agent_pss_mb_median": agent_pss[len(agent_pss) // 2] if agent_pss else float("nan"),
        "idle_traffic_per_s": traffic.rates() if traffic is not None else {},
    }


def print_idle(row: Mapping[str, object]) -> None:
    """The idle figures as Markdown tables."""
    cpu = row.get("idle_agent_cpu_ms_per_s") or {}
    wake = row.get("idle_agent_wakeups_per_s") or {}
    print(f"\nIdle, clock held {row.get('idle_wall_s')} s, {row.get('idle_agents')} agents "
          f"(all agents together {row.get('idle_agents_total_cpu_pct', float('nan')):.1f} % of a core):")
    print("| agent thread group (median agent) | CPU ms per wall s | wake-ups per wall s |")
    print("|---|---|---|")
    for group in sorted(cpu, key=lambda g: (g == "total", -cpu[g])):  # type: ignore[index]
        print(f"| {group} | {cpu[group]:.2f} | {wake.get(group, 0.0):.1f} |")  # type: ignore[index,union-attr]
    print("| process | CPU ms per wall s |")
    print("|---|---|")
    for name, ms in sorted((row.get("idle_service_cpu_ms_per_s") or {}).items()):  # type: ignore[union-attr]
        print(f"| {name} | {ms:.1f} |")
    traffic = row.get("idle_traffic_per_s") or {}
    if traffic:
        print("| loopback traffic | per wall s |")
        print("|---|---|")
        for name, rate in traffic.items():  # type: ignore[union-attr]
            print(f"| {name} | {rate:.1f} |")


def main() -> int:
    import argparse  # noqa: PLC0415
    import json  # noqa: PLC0415

    from bench.mission_processes import run_once  # noqa: PLC0415 - heavy (the ground station)

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="circle")
    p.add_argument("--mode", default="improved")
    p.add_argument("--duration", type=float, default=20.0)
    p.add_argument("--idle-s", type=float, default=30.0, help="wall seconds the clock is held (< 60)")
    p.add_argument("--set", action="append", default=[], dest="overrides", metavar="KEY=VALUE")
    p.add_argument("--out", type=Path, default=Path("runs/bench-agent-idle"))
    args = p.parse_args()
    row = run_once(args.scenario, tuple(args.overrides), 1.0, args.duration, args.out, args.mode, idle_s=args.idle_s)
    print(json.dumps(row), flush=True)
    print_idle(row)
    return 0


if __name__ == "__main__":
    sys.exit(main())
