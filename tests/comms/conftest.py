"""Fixtures for the comms tests: fresh loopback Zenoh endpoints and process cleanup."""

from __future__ import annotations

import os
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
