"""Liveliness and staleness across real processes: kill -9 and a hung (stopped) agent."""

from __future__ import annotations

import json
import os
import select
import signal
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from comms.keys import MissionKeys
from comms.neighbour_table import NeighbourTable
from comms.swarm_link import SwarmLink
from comms.zenoh_session import ZenohConfig, ZenohSession

pytestmark = pytest.mark.integration
AGENT = str(Path(__file__).with_name("comms_agent_proc.py"))


def _start_agents(spawn: Callable, hub_ep: str, mission: str, ids: list[int]) -> dict:
    procs = {i: spawn(AGENT, "--hub", hub_ep, "--mission", mission, "--id", str(i), "--duration-s", "60") for i in ids}
    for p in procs.values():
        assert p.stdout.readline().strip() == "READY"
    return procs


def _read_until(proc: subprocess.Popen, line: str, timeout_s: float) -> bool:
    """Read the process's stdout lines until ``line`` appears (True) or the timeout passes (False)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        ready, _, _ = select.select([proc.stdout], [], [], max(0.0, deadline - time.monotonic()))
        if not ready:
            return False
        text = proc.stdout.readline()
        if not text:
            return False
        if text.strip() == line:
            return True
    return False


def _pump(link: SwarmLink, table: NeighbourTable, t0: float, until: Callable[[], bool], timeout_s: float) -> float | None:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        link.update_table(table, time.monotonic() - t0)
        if until():
            return time.monotonic()
        link.wait(0.01)
    return None


def test_kill_9_is_reported_to_ground_station_and_neighbours(free_endpoint: Callable[[], str], spawn: Callable) -> None:
    hub_ep = free_endpoint()
    mission = "lv1"
    keys = MissionKeys(mission)
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        gcs = SwarmLink(hub, keys, None, via_radio=False, participant="gcs")
        table = NeighbourTable(own_id=None, period_s=0.05)
        t0 = time.monotonic()
        procs = _start_agents(spawn, hub_ep, mission, [1, 2, 3])
        assert _pump(gcs, table, t0, lambda: table.fresh_ids == [1, 2, 3], 15.0)
        time.sleep(0.5)  # let the agents hear each other
        killed_at = time.monotonic()
        os.kill(procs[2].pid, signal.SIGKILL)
        seen = _pump(gcs, table, t0, lambda: 2 in table.dead_ids, 10.0)
        assert seen is not None and seen - killed_at < 3.0  # SPEC §7: noticed within 3 s
        assert table.fresh_ids == [1, 3]
        events = [(e.vehicle_id, e.event) for e in table.take_events()]
        assert (2, "dead") in events
        for i in (1, 3):
            # each neighbour learns it through liveliness too (generous timeout: the machine may be loaded)
            assert _read_until(procs[i], "DEAD 2", 20.0), f"agent {i} never reported 2 dead"
            procs[i].send_signal(signal.SIGTERM)
            out, _ = procs[i].communicate(timeout=20)
            record = json.loads(out.strip().splitlines()[-1])
            assert set(record["heard"]) == {str(j) for j in (1, 2, 3) if j != i}


def test_hung_agent_goes_stale_then_rejoins(free_endpoint: Callable[[], str], spawn: Callable) -> None:
    hub_ep = free_endpoint()
    mission = "lv2"
    keys = MissionKeys(mission)
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        gcs = SwarmLink(hub, keys, None, via_radio=False)
        # the agent sends at 20 Hz; judge it on 0.2 s periods (stale after 0.6 s) so that a loaded machine's
        # scheduling gaps are not mistaken for a hang
        table = NeighbourTable(own_id=None, period_s=0.2, stale_periods=3)
        t0 = time.monotonic()
        procs = _start_agents(spawn, hub_ep, mission, [7])
        assert _pump(gcs, table, t0, lambda: table.fresh_ids == [7], 15.0)
        stopped_at = time.monotonic()
        os.kill(procs[7].pid, signal.SIGSTOP)
        try:
            seen = _pump(gcs, table, t0, lambda: table.stale_ids == [7], 5.0)
            assert seen is not None and 0.4 < seen - stopped_at < 3.0  # three 0.2 s periods minus the last gap, plus slack
            assert table.dead_ids == []  # a hung process still holds its liveliness token
        finally:
            os.kill(procs[7].pid, signal.SIGCONT)
        assert _pump(gcs, table, t0, lambda: table.fresh_ids == [7], 10.0)
        assert [e.event for e in table.take_events()][-2:] == ["stale", "rejoined"]
