"""Helpers for whole-mission tests: ports that never clash with a user's mission, and the no-orphan check."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def pids_of_run(out_dir: Path) -> dict[str, int]:
    path = out_dir / "processes.json"
    return json.loads(path.read_text()) if path.exists() else {}


def alive_pids(pids: dict[str, int]) -> dict[str, int]:
    """Those of ``pids`` that still exist and are not zombies."""
    alive = {}
    for name, pid in pids.items():
        try:
            status = Path(f"/proc/{pid}/status").read_text()
        except OSError:
            continue
        if "\nState:\tZ" not in status:
            alive[name] = pid
    return alive


def assert_no_orphans(out_dir: Path, wait_s: float = 5.0) -> None:
    pids = pids_of_run(out_dir)
    assert pids, "the run recorded no process ids"
    deadline = time.monotonic() + wait_s
    while alive_pids(pids) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert alive_pids(pids) == {}, f"orphan processes left behind: {alive_pids(pids)}"


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
