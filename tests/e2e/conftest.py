"""Helpers for whole-mission tests: ports that never clash with a user's mission, and the no-orphan check."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture
def mission_cli():
    """Run ``python -m gcs.mission ...`` as the README does; kills the whole group if the test fails midway."""
    started: list[subprocess.Popen[str]] = []

    def start(args: list[str], zenoh_endpoint: str) -> subprocess.Popen[str]:
        env = dict(os.environ, FLOODWATCH_ZENOH_ENDPOINT=zenoh_endpoint, PYTHONUNBUFFERED="1")
        proc = subprocess.Popen([sys.executable, "-m", "gcs.mission", *args], cwd=REPO, env=env, text=True,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
        started.append(proc)
        return proc

    yield start
    for proc in started:
        if proc.poll() is None:
            os.killpg(proc.pid, 9)
            proc.wait(timeout=10)
