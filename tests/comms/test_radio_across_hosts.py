"""The radio emulator forwards across hosts exactly as the README's multi-machine section writes it.

Two of the network namespaces of the ``namespaces`` fixture (made and removed by it, as root; skipped with the
kernel's reason where it refuses), joined by a veth link: ``hostA`` (the ground-station host: the mission hub with
its router bridging it to the other host, the radio emulator and the simulator's truth) and ``hostB`` (a drone host: its router and three drones,
TLS clients of it). The README's own command lines are run (certificates, both routers with TLS and the access
control, the radio), with only the interpreter's path replaced; ``hostB`` resolves ``hostA`` through its own
``/etc/netns/<name>/hosts``, which ``ip netns exec`` mounts over ``/etc/hosts``.

Each state crosses the veth twice (hostB -> hostA's hub -> the radio -> hostB): drones 1 and 2, 10 m apart, hear
each other; drone 3, 100 m away, hears nobody and nobody hears it.
"""

from __future__ import annotations

import json
import re
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from comms.key_file import create_key_file

pytestmark = pytest.mark.integration

REPO = Path(__file__).resolve().parents[2]
HERE = Path(__file__).parent
DRONES = {1: (0.0, 0.0), 2: (10.0, 0.0), 3: (100.0, 0.0)}
_HOST_LINE = re.compile(r"^(?:(host[A-Z])\$ )?\.venv/bin/python -m (comms\.(?:router|radio|certificates)) (.*)$")


def readme_commands() -> list[tuple[str | None, str, list[str]]]:
    """(host or None, module, arguments) of every README line that runs the certificates, a router or the radio,
    continuation lines joined."""
    text = (REPO / "README.md").read_text().replace("\\\n", " ")
    commands = []
    for line in text.splitlines():
        match = _HOST_LINE.match(line.strip())
        if match:
            commands.append((match.group(1), match.group(2), shlex.split(match.group(3))))
    return commands


def _wait_for(path: Path, text: str, procs: list[subprocess.Popen], timeout_s: float = 30.0) -> None:
    deadline = time.monotonic() + timeout_s
    while text not in (path.read_text() if path.exists() else ""):
        assert all(p.poll() is None for p in procs), f"a process ended early: {path.read_text()[-2000:]}"
        assert time.monotonic() < deadline, f"{text!r} not in {path}: {path.read_text()[-2000:]}"
        time.sleep(0.1)


def test_readme_radio_command_forwards_between_two_hosts(namespaces, tmp_path: Path) -> None:  # noqa: ANN001
    commands = readme_commands()
    modules = sorted((host or "", module) for host, module, _ in commands)
    assert modules == [("", "comms.certificates"), ("hostA", "comms.radio"), ("hostA", "comms.router"),
                       ("hostA", "comms.router"), ("hostB", "comms.router")], modules
    where = {"hostA": namespaces.names["gcs"], "hostB": namespaces.names["da"]}
    namespaces.name_hosts("da", {"hostA": namespaces.gcs_address("da")})
    env = {"PYTHONPATH": str(REPO), "PATH": "/usr/sbin:/usr/bin:/sbin:/bin"}
    (tmp_path / "plans").mkdir()
    create_key_file(tmp_path / "plans" / "mission.key")  # what `python -m gcs.plan circle --out plans` writes beside the plans
    procs: list[subprocess.Popen] = []

    def start(host: str, name: str, args: list[str]) -> Path:
        log = tmp_path / f"{host}-{name}.log"
        with log.open("w") as out:
            procs.append(subprocess.Popen(["ip", "netns", "exec", where[host], sys.executable, *args], cwd=tmp_path,
                                          env=env, stdout=out, stderr=subprocess.STDOUT))
        return log

    try:
        for host, module, args in commands:
            if host is None:
                subprocess.run([sys.executable, "-m", module, *args], cwd=tmp_path, env=env, check=True,
                               capture_output=True, timeout=60)
        logs = {}
        for host, module, args in commands:
            if host is not None:
                logs[(host, module, args[1])] = start(host, f"{module}-{len(logs)}", ["-m", module, *args])
                if module == "comms.router":
                    _wait_for(logs[(host, module, args[1])], "listening on", procs)
        truth = start("hostA", "truth", [str(HERE / "truth_proc.py"), "--connect", "tcp/127.0.0.1:7447", "--mission",
                                         "circle", "--vehicles", *(f"{v}:{e},{n}" for v, (e, n) in DRONES.items())])
        _wait_for(truth, "READY", procs)
        drone_identity = next(args for host, module, args in commands if (host, module) == ("hostB", "comms.router"))
        tls = [a for flag in ("--tls-ca", "--tls-cert", "--tls-key")
               for a in (flag, drone_identity[drone_identity.index(flag) + 1])]
        drones = {vid: start("hostB", f"drone_{vid}", [str(HERE / "comms_agent_proc.py"), "--hub", "tls/127.0.0.1:7447",
                                                        "--client", "--mission", "circle", "--id", str(vid), "--via-radio",
                                                        "--key-file", "plans/mission.key", "--duration-s", "3", *tls])
                  for vid in DRONES}
        for p in procs[-len(DRONES):]:
            p.wait(timeout=60)
    finally:
        for p in procs:
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
    heard = {vid: json.loads(log.read_text().strip().splitlines()[-1])["heard"] for vid, log in drones.items()}
    radio = next(log for (_, module, _), log in logs.items() if module == "comms.radio").read_text()
    assert heard[1].get("2", 0) >= 20 and heard[2].get("1", 0) >= 20, (heard, radio[-500:])
    assert heard[3] == {} and "3" not in heard[1] and "3" not in heard[2], heard
    assert re.search(r"rejected 0, no truth 0", radio), radio[-500:]
