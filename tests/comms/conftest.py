"""Fixtures for the comms tests: fresh loopback Zenoh endpoints and process cleanup."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
AGENT_PROC = Path(__file__).with_name("comms_agent_proc.py")


@pytest.fixture
def free_endpoint(zenoh_endpoint: Callable[[], str]) -> Callable[[], str]:
    """Returns a function giving a fresh ``tcp/127.0.0.1:<port>`` (the root conftest's ``zenoh_endpoint``)."""
    return zenoh_endpoint


@pytest.fixture
def spawn() -> Iterator[Callable[..., subprocess.Popen]]:
    """Start Python processes from the repo root; every one is killed and reaped at teardown."""
    procs: list[subprocess.Popen] = []

    def start(*args: str) -> subprocess.Popen:
        env = dict(os.environ, PYTHONPATH=str(REPO))
        p = subprocess.Popen([sys.executable, *args], cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        procs.append(p)
        return p

    try:
        yield start
    finally:
        for p in procs:
            if p.poll() is None:
                p.kill()
            try:
                p.communicate(timeout=10)
            except subprocess.TimeoutExpired:
                pass


SPOKES = ("da", "db", "rc")  # drones_a, drones_b, rescue: each 10.216.<k>.2, the gcs side 10.216.<k>.1
_NETNS_ETC = Path("/etc/netns")


def _ip(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["ip", *args], capture_output=True, text=True, timeout=10)


class Namespaces:
    """Four network namespaces, ``gcs`` joined to each of ``SPOKES`` by its own veth link: ``names[spoke]`` and
    ``names["gcs"]``; addresses only inside them."""

    router_port = 7448
    """Where the ground-station host's router listens on its veth links."""

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

    def name_hosts(self, where: str, hosts: dict[str, str]) -> None:
        """Give namespace ``where`` its own ``/etc/hosts``: the machine's plus ``hosts`` (name -> address); ``ip
        netns exec`` mounts ``/etc/netns/<name>/hosts`` over ``/etc/hosts``. Removed with the namespaces."""
        folder = _NETNS_ETC / self.names[where]
        folder.mkdir(parents=True, exist_ok=True)
        lines = "".join(f"{address} {name}\n" for name, address in hosts.items())
        (folder / "hosts").write_text(Path("/etc/hosts").read_text() + lines)

    def remove(self) -> None:
        for name in self.made:
            _ip("netns", "del", name)  # removes its veth ends too
            shutil.rmtree(_NETNS_ETC / name, ignore_errors=True)
        try:
            _NETNS_ETC.rmdir()  # only when empty: another run's namespaces may still use it
        except OSError:
            pass

    def address(self, spoke: str) -> str:
        """``spoke``'s own address on its veth link to the ground-station host."""
        return f"10.216.{SPOKES.index(spoke) + 1}.2"

    def gcs_address(self, spoke: str) -> str:
        """The ground-station host's address on its veth link to ``spoke``."""
        return f"10.216.{SPOKES.index(spoke) + 1}.1"

    def endpoint(self, spoke: str) -> str:
        """The ground station's router as seen from ``spoke`` (its side of their veth link)."""
        return f"tcp/{self.gcs_address(spoke)}:{self.router_port}"


@pytest.fixture
def namespaces() -> Iterator[Namespaces]:
    """The four namespaces, made as root and removed afterwards; skipped (with the reason) where that is refused."""
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
