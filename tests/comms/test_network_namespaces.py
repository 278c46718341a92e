"""Several hosts across real network stacks: Linux network namespaces joined by veth links, a Zenoh router in each.

Four namespaces, made and removed by this test (as root; skipped with the kernel's reason where it refuses), with
addresses only inside them:

* ``gcs``: the ground station's router (``python -m comms.router``) and a ground-station process that hears every
  drone's state and publishes the flood polygon on the public key;
* ``drones_a`` and ``drones_b``: each its own router, connected to the ground station's router across its veth
  link, and the agents of two drones (each a Zenoh client of its local router, publishing its state at 20 Hz and
  recording whom it hears);
* ``rescue``: a rescue-centre listener (``python -m comms.listen``) connected to the ground station's router.

Every link between namespaces is a veth pair to ``gcs`` (a star: drones_a ↔ gcs, drones_b ↔ gcs, rescue ↔ gcs), so
every state crosses at least one veth and the drones of A hear those of B across two. What this test does not
carry across the namespaces: the autopilots (the mock PX4 fleet is one simulator process with one clock, and its
MAVLink links stay on one host) and the swarm radio's loss (this kernel has no netem; loss stays in the radio
model). The full mission over the same topology is in the README's section on several machines.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

pytestmark = pytest.mark.integration

REPO = Path(__file__).resolve().parents[2]
AGENT_PROC = Path(__file__).with_name("comms_agent_proc.py")
GCS_PROC = Path(__file__).with_name("comms_gcs_proc.py")
PORT = 7448
SPOKES = ("da", "db", "rc")  # drones_a, drones_b, rescue: each 10.216.<k>.2, the gcs side 10.216.<k>.1


def _ip(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["ip", *args], capture_output=True, text=True, timeout=10)


class Namespaces:
    """The four namespaces and their veth links; ``names[spoke]`` and ``names["gcs"]``."""

    def __init__(self) -> None:
        tag = f"fw{os.getpid() % 100000}"
        self.names = {"gcs": f"{tag}gcs", **{s: f"{tag}{s}" for s in SPOKES}}
        self.made: list[str] = []

    def build(self) -> str | None:
        """Make everything; the first refusal's message (the test is then skipped), or None."""
        for name in self.names.values():
            result = _ip("netns", "add", name)
            if result.returncode != 0:
                return f"ip netns add refused: {result.stderr.strip()}"
            self.made.append(name)
            _ip("-n", name, "link", "set", "lo", "up")
        gcs = self.names["gcs"]
        for k, spoke in enumerate(SPOKES, start=1):
            inner, outer = f"v{spoke}{os.getpid() % 10000}", f"g{spoke}{os.getpid() % 10000}"
            steps = [
                ("link", "add", inner, "type", "veth", "peer", "name", outer),
                ("link", "set", inner, "netns", self.names[spoke]),
                ("link", "set", outer, "netns", gcs),
                ("-n", self.names[spoke], "addr", "add", f"10.216.{k}.2/24", "dev", inner),
                ("-n", gcs, "addr", "add", f"10.216.{k}.1/24", "dev", outer),
                ("-n", self.names[spoke], "link", "set", inner, "up"),
                ("-n", gcs, "link", "set", outer, "up"),
                ("-n", self.names[spoke], "route", "add", "default", "via", f"10.216.{k}.1"),
            ]
            for step in steps:
                result = _ip(*step)
                if result.returncode != 0:
                    return f"ip {' '.join(step)} refused: {result.stderr.strip()}"
        return None

    def remove(self) -> None:
        for name in self.made:
            _ip("netns", "del", name)  # removes its veth ends too

    def endpoint(self, spoke: str) -> str:
        """The ground station's router as seen from ``spoke`` (its side of their veth link)."""
        return f"tcp/10.216.{SPOKES.index(spoke) + 1}.1:{PORT}"


@pytest.fixture
def namespaces() -> Iterator[Namespaces]:
    if os.geteuid() != 0:
        pytest.skip("network namespaces need root")
    if shutil.which("ip") is None:
        pytest.skip("no iproute2 (ip) on this host")
    ns = Namespaces()
    try:
        refused = ns.build()
        if refused is not None:
            pytest.skip(f"the kernel refused: {refused}")
        yield ns
    finally:
        ns.remove()


def test_states_and_polygon_cross_veth_links_between_four_namespaces(namespaces: Namespaces) -> None:
    ns = namespaces.names
    procs: list[subprocess.Popen] = []
    env = dict(os.environ, PYTHONPATH=str(REPO))

    def start(where: str, *args: str) -> subprocess.Popen:
        p = subprocess.Popen(["ip", "netns", "exec", ns[where], sys.executable, *args], cwd=REPO, env=env,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        procs.append(p)
        return p

    mission = "nets"
    try:
        routers = [start("gcs", "-m", "comms.router", "--listen", f"tcp/0.0.0.0:{PORT}")]
        assert "listening on" in routers[0].stderr.readline()
        for spoke in ("da", "db"):
            routers.append(start(spoke, "-m", "comms.router", "--listen", f"tcp/127.0.0.1:{PORT}",
                                 "--connect", namespaces.endpoint(spoke)))
            assert "listening on" in routers[-1].stderr.readline()
        local = f"tcp/127.0.0.1:{PORT}"
        gcs = start("gcs", str(GCS_PROC), "--hub", local, "--mission", mission, "--drones", "1,2,3,4",
                    "--duration-s", "14")
        listener = start("rc", "-m", "comms.listen", "--mission", mission, "--connect", namespaces.endpoint("rc"),
                         "--duration-s", "14", "--every-s", "0.5")
        agents = {vid: start(spoke, str(AGENT_PROC), "--hub", local, "--mission", mission, "--id", str(vid),
                             "--claim", str(vid), "0", "--duration-s", "8", "--client")
                  for vid, spoke in ((1, "da"), (2, "da"), (3, "db"), (4, "db"))}
        heard = {vid: json.loads(p.communicate(timeout=60)[0].strip().splitlines()[-1]) for vid, p in agents.items()}
        gcs_out, gcs_err = gcs.communicate(timeout=60)
        listened, _ = listener.communicate(timeout=60)
    finally:
        for p in procs:
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
        deadline = time.monotonic() + 20
        for p in procs:
            try:
                p.communicate(timeout=max(0.1, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                p.kill()
                p.communicate()
    for vid, result in heard.items():
        others = {str(o) for o in (1, 2, 3, 4) if o != vid}
        assert others <= set(result["heard"]), f"drone {vid} heard only {result['heard']}"
    summary = json.loads(gcs_out.strip().splitlines()[-1])
    assert summary["heard"] == [1, 2, 3, 4] and summary["polygons"] > 0, gcs_err
    records = [json.loads(line) for line in listened.splitlines() if line.startswith("{")]
    state_senders = {r["id"] for r in records if r.get("key", "").endswith("/state")}
    assert {1, 2, 3, 4} <= state_senders
    assert any(r.get("key", "").endswith("/gcs/polygon") for r in records)
