"""The real mission across real network stacks: Linux network namespaces joined by veth links, a Zenoh router in each.

Four namespaces, made and removed by this test (as root; skipped with the kernel's reason where it refuses), with
addresses only inside them:

* ``gcs`` (the ground-station host): ``python -m gcs.mission circle --no-agents`` with its mission hub, the
  simulation it starts (the mock PX4 fleet with the simulator bridge, the cameras, the radio emulator) and the
  ground station as a radio node, plus the host's router (``python -m comms.router``) bridging the hub to the veths;
* ``drones_a`` and ``drones_b`` (two companion-computer hosts): each its own router, connected to the ground
  station's across its veth, and the real agents (``python -m vehicle_agents``) of some of the drones, Zenoh
  clients of their local router, started by the test from the plans the ground station wrote, as the drones'
  owners would start them;
* ``rescue``: a rescue-centre listener (``python -m comms.listen``) connected to the ground station's router.

Where the autopilots run: the simulated PX4s are all in the fleet process on the ground-station host (one
simulator, one clock), bound to every interface (``--fleet-bind 0.0.0.0``); each vehicle's onboard MAVLink link
goes to its companion computer's address (``--onboard-partner IDS=IP``, PX4's ``mavlink start -t``), where its
agent listens (``--mavlink udpin://0.0.0.0:<port>``, MAVSDK's URL). Links that cross a veth: every onboard MAVLink
link (gcs ↔ drones_a/b), every agent's Zenoh traffic (its states, the radio's inbox bundles, the paced clock's
ticks and acknowledgements, the ground station's commands: drones_a/b ↔ gcs router ↔ hub) and the rescue centre's
subscription (rescue ↔ gcs). The ground station's own MAVLink link and the simulation's processes stay on the
ground-station host's loopback. The swarm radio's loss stays in the radio model (this kernel has no netem).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from gcs.processes import ZENOH_ENDPOINT_ENV
from gcs.processes.launch import ProcessOptions, agent_command

pytestmark = pytest.mark.integration

REPO = Path(__file__).resolve().parents[2]


def _stop(procs: list[subprocess.Popen]) -> None:
    """SIGTERM every process still running (the ground station stops its own children), then wait; kill stragglers."""
    for p in procs:
        if p.poll() is None:
            p.send_signal(signal.SIGTERM)
    deadline = time.monotonic() + 30
    for p in procs:
        try:
            p.communicate(timeout=max(0.1, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            p.kill()
            p.communicate()


def _fly_across_namespaces(namespaces: Namespaces, out: Path, overrides: list[str], drones_a: list[int],
                           drones_b: list[int], duration_s: float) -> tuple[int, list[dict]]:
    """Run the mission over the four namespaces: the ground station's exit code and the rescue centre's records.
    Every process's output is in ``out/hosts``."""
    ns = namespaces.names
    procs: list[subprocess.Popen] = []
    env = {k: v for k, v in os.environ.items() if k != ZENOH_ENDPOINT_ENV} | {"PYTHONPATH": str(REPO)}
    logs = out / "hosts"
    logs.mkdir(parents=True)

    def start(where: str, name: str, args: list[str]) -> subprocess.Popen:
        with (logs / f"{where}-{name}.out").open("w") as stdout, (logs / f"{where}-{name}.log").open("w") as stderr:
            p = subprocess.Popen(["ip", "netns", "exec", ns[where], sys.executable, "-m", *args], cwd=REPO, env=env,
                                 stdout=stdout, stderr=stderr)
        procs.append(p)
        return p

    def partner(ids: list[int], spoke: str) -> list[str]:
        return ["--onboard-partner", f"{ids[0]}-{ids[-1]}={namespaces.address(spoke)}"]

    run = out / "run"
    try:
        gcs = start("gcs", "gcs", ["gcs.mission", "circle", "--no-agents", "--fleet-bind", "0.0.0.0",
                                   *partner(drones_a, "da"), *partner(drones_b, "db"), "--duration", f"{duration_s:g}",
                                   "--out", str(run), "--no-live", "--no-dashboard",
                                   *(a for o in overrides for a in ("--set", o))])
        plans = run / "plan"
        deadline = time.monotonic() + 60
        while not all((plans / f"agent_{v}.json").exists() for v in drones_a + drones_b):
            assert gcs.poll() is None and time.monotonic() < deadline, "the ground station wrote no plans"
            time.sleep(0.2)
        start("gcs", "router", ["comms.router", "--listen", f"tcp/0.0.0.0:{namespaces.router_port}", "--connect",
                                "tcp/127.0.0.1:7447"])
        for spoke in ("da", "db"):
            start(spoke, "router", ["comms.router", "--listen", "tcp/127.0.0.1:7447", "--connect",
                                    namespaces.endpoint(spoke)])
        start("rc", "listen", ["comms.listen", "--mission", "circle", "--connect", namespaces.endpoint("rc"),
                               "--every-s", "0.5"])
        options = ProcessOptions("circle", zenoh_endpoint="tcp/127.0.0.1:7447")
        for spoke, ids in (("da", drones_a), ("db", drones_b)):
            for vid in ids:
                start(spoke, f"agent_{vid}", [*agent_command(options, vid, plans / f"agent_{vid}.json"),
                                              "--zenoh-mode", "client"])
        code = gcs.wait(timeout=300)
        time.sleep(1.0)  # the last polygon reaches the listener
    finally:
        _stop(procs)
    listened = (logs / "rc-listen.out").read_text()
    return code, [json.loads(line) for line in listened.splitlines() if line.startswith("{")]


def _check_mission(code: int, records: list[dict], out: Path, vehicle_ids: list[int]) -> dict:
    """The mission ran to its end, and the rescue centre got the polygon and every drone's state; the metrics."""
    run = out / "run"
    assert code == 0, (run / "events.log").read_text()[-3000:] if (run / "events.log").exists() else code
    state_senders = {r["id"] for r in records if r.get("key", "").endswith("/state")}
    assert set(vehicle_ids) <= state_senders, f"the rescue centre heard only {sorted(state_senders)}"
    assert any(r.get("key", "").endswith("/gcs/polygon") and r.get("vertices", 0) >= 3 for r in records)
    return json.loads((run / "metrics.json").read_text())


def test_a_small_mission_flies_with_its_agents_on_two_other_hosts(namespaces: Namespaces, tmp_path: Path) -> None:
    """Three drones (a boundary drone per group and the leader) at 5 m, 3 s of flood clock: the default suite's
    variant, every part of the full one but its length."""
    overrides = ["fleet.boundary_per_group=1", "fleet.follower_layers=[]", "altitude_m=5", "radio.gcs_lossless=false"]
    code, records = _fly_across_namespaces(namespaces, tmp_path, overrides, [1, 2], [3], 3.0)
    metrics = _check_mission(code, records, tmp_path, [1, 2, 3])
    assert metrics["summary"]["vehicles"] == 3


@pytest.mark.slow
def test_the_circle_mission_flies_with_its_agents_on_two_other_hosts(namespaces: Namespaces, tmp_path: Path) -> None:
    """The paper's 13 drones, 30 s of flood clock, the ground station as a radio node on a 15 m radio."""
    overrides = ["radio.range_m=15", "radio.gcs_lossless=false"]
    code, records = _fly_across_namespaces(namespaces, tmp_path, overrides, list(range(1, 8)), list(range(8, 14)), 30.0)
    metrics = _check_mission(code, records, tmp_path, list(range(1, 14)))
    assert metrics["summary"]["polygon_iou_final"] >= 0.97
