"""The start-up stall limit (``--startup-timeout-s``): a run whose agents cannot start ends after the limit, not 60 s.

Real processes: the fleet, cameras and radio start as in any mission, but every agent listens for its autopilot on a
port no vehicle sends to, so none ever connects.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from gcs.processes import ProcessOptions, run_processes
from gcs.scenario import load_scenario

pytestmark = pytest.mark.integration
TWO_BOUNDARY_DRONES = ("fleet.boundary_per_group=1", "fleet.leaders=0", "fleet.follower_layers=[]")
STARTUP_TIMEOUT_S = 2.0


def _alive(pid: int) -> bool:
    try:
        return "\nState:\tZ" not in Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False


def test_short_startup_limit_ends_a_run_whose_agents_cannot_start(
    tmp_path: Path, udp_ports: Callable[[int], int], zenoh_endpoint: Callable[[], str],
) -> None:
    base, gcs, silent = udp_ports(2), udp_ports(1), udp_ports(1)
    out = tmp_path / "run"
    options = ProcessOptions(
        scenario_arg="circle", overrides=TWO_BOUNDARY_DRONES, duration_s=5.0, out_dir=out, mission="stall",
        mavlink_base_port=base, gcs_port=gcs, zenoh_endpoint=zenoh_endpoint(), live=False,
        startup_timeout_s=STARTUP_TIMEOUT_S,
        extra_agent_args=("--mavlink", f"udpin://0.0.0.0:{silent}", "--connect-timeout", "120"),
    )
    started = time.monotonic()
    code = run_processes(load_scenario("circle", TWO_BOUNDARY_DRONES), options)
    elapsed_s = time.monotonic() - started
    events = (out / "events.log").read_text()
    assert code == 1, events
    assert f"start-up stalled: nothing came up for {STARTUP_TIMEOUT_S:g} s (0 of 2 agents" in events
    assert elapsed_s < 60.0, "the default limit was used, not the option"
    pids = json.loads((out / "processes.json").read_text())
    assert set(pids) >= {"sim", "cameras", "radio", "agent_1", "agent_2"}
    deadline = time.monotonic() + 5.0
    while any(_alive(pid) for pid in pids.values()) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not [name for name, pid in pids.items() if _alive(pid)], "every process started is stopped"
