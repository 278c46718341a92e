"""Fixtures for the comms tests: loopback ports in the comms range (23000-24999) and process cleanup."""

from __future__ import annotations

import os
import random
import socket
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
AGENT_PROC = Path(__file__).with_name("comms_agent_proc.py")
_rng = random.Random(os.getpid())


def _port_is_free(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind(("127.0.0.1", port))
        except OSError:
            return False
    return True


@pytest.fixture
def free_endpoint() -> Callable[[], str]:
    """Returns a function giving a fresh ``tcp/127.0.0.1:<port>`` with a free port in 23000-24999."""

    def pick() -> str:
        for _ in range(200):
            port = _rng.randint(23000, 24999)
            if _port_is_free(port):
                return f"tcp/127.0.0.1:{port}"
        raise RuntimeError("no free port in 23000-24999")

    return pick


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
