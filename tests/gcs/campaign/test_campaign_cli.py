"""``python -m gcs.campaign`` end to end on short missions: usage errors, a failing run, resume, a killed worker,
and an external dask scheduler and worker on loopback."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import psutil
import pytest

from gcs.campaign.cli import main
from gcs.campaign.grid import Mode, RunSpec
from gcs.campaign.runner import run_one
from gcs.campaign.store import read_rows

REPO = Path(__file__).resolve().parents[3]
DASK = Path(sys.executable).with_name("dask")
SHORT = ["--set", "duration_s=1", "--mode", "paper"]


def campaign(*args: str, timeout_s: float = 120.0) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gcs.campaign", *args], cwd=REPO, capture_output=True, text=True,
                          timeout=timeout_s)


def stop_group(proc: subprocess.Popen) -> None:
    """SIGTERM the process group, SIGKILL what is left after 10 s."""
    for sig, wait_s in ((signal.SIGTERM, 10.0), (signal.SIGKILL, 5.0)):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            return
        try:
            proc.wait(timeout=wait_s)
            deadline = time.monotonic() + wait_s
            while time.monotonic() < deadline:
                os.killpg(proc.pid, 0)
                time.sleep(0.1)
        except (subprocess.TimeoutExpired, ProcessLookupError):
            pass


@pytest.mark.parametrize(("args", "named"), [
    (["circle", "--grid", "radio.los=0,0.3"], "radio.los: unknown key (did you mean radio.loss?)"),
    (["circle", "--grid", "radio.loss=0,1.3"], "--grid radio.loss=1.3: radio.loss: must be <= 1, got 1.3"),
    (["circle", "--seeds", "1-x"], "--seeds '1-x'"),
    (["circel"], "unknown scenario 'circel'"),
    (["circle", "--mode", "paper,best"], "--mode 'best'"),
    (["circle", "--set", "flood.radius_end_m"], "--set 'flood.radius_end_m'"),
    (["circle", "--grid", "control.pdot_reading=full,sometimes"], "control.pdot_reading: must be one of"),
])
def test_bad_arguments_exit_2_with_one_line_before_anything_starts(
        args: list[str], named: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "camp"
    assert main([*args, "--out", str(out)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.count("\n") == 1 and captured.err.startswith("gcs.campaign: ") and named in captured.err
    assert not out.exists()


@pytest.mark.integration
def test_bad_key_from_the_command_line(tmp_path: Path) -> None:
    done = campaign("circle", "--grid", "radio.los=0,0.3", "--out", str(tmp_path / "camp"))
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr == "gcs.campaign: --grid radio.los: unknown key (did you mean radio.loss?)\n"
    assert not (tmp_path / "camp").exists()


@pytest.mark.integration
def test_a_failing_run_is_recorded_the_rest_goes_on_and_a_rerun_skips_both(tmp_path: Path) -> None:
    """A radius of 1e300 m passes validation (the flood at t = 0 is fine) and overflows in the run."""
    out = tmp_path / "camp"
    args = ["circle", "--seeds", "1", "--grid", "flood.radius_end_m=16,1e300", *SHORT, "--workers", "2",
            "--out", str(out)]
    first = campaign(*args)
    assert first.returncode == 1, first.stderr
    rows = {row["cell"]: row for row in read_rows(out)}
    assert set(rows) == {"flood.radius_end_m=16", "flood.radius_end_m=1e300"}
    assert rows["flood.radius_end_m=1e300"]["error"].startswith("OverflowError")
    ok = rows["flood.radius_end_m=16"]
    assert ok["error"] is None and ok["grid:flood.radius_end_m"] == "16" and ok["seed"] == 1
    assert ok["polygon_iou_final"] > 0 and ok["wall_s"] > 0 and ok["cpu_s"] > 0 and ok["code_version"]
    assert "FAILED circle paper seed 1 [flood.radius_end_m=1e300]: OverflowError" in first.stdout
    assert (out / "summary.md").read_text().count("OverflowError") == 1
    assert any((out / "plots").glob("circle__coverage_final__flood.radius_end_m.png"))

    again = campaign(*args)
    assert again.returncode == 1
    assert "2 runs, 2 already done, 0 to run" in again.stdout
    assert len(read_rows(out)) == 2

    same = run_one(RunSpec("circle", Mode.PAPER, 1, (("flood.radius_end_m", "16"),), ("duration_s=1",)), "test")
    assert {k: same[k] for k in ("polygon_iou_final", "coverage_final", "tracking_rms_m", "min_pairwise_distance_m")} \
        == {k: ok[k] for k in ("polygon_iou_final", "coverage_final", "tracking_rms_m", "min_pairwise_distance_m")}


@pytest.fixture
def started() -> Iterator[list[subprocess.Popen]]:
    """Processes a test starts, each in its own process group, all stopped afterwards whatever happens."""
    procs: list[subprocess.Popen] = []
    try:
        yield procs
    finally:
        for proc in reversed(procs):
            stop_group(proc)


def _worker_processes(root: psutil.Process) -> list[psutil.Process]:
    found = []
    for child in root.children(recursive=True):
        try:
            if "spawn_main" in " ".join(child.cmdline()):
                found.append(child)
        except psutil.NoSuchProcess:
            continue
    return found


@pytest.mark.integration
@pytest.mark.slow
def test_a_killed_worker_has_its_runs_retried(tmp_path: Path, started: list[subprocess.Popen]) -> None:
    out = tmp_path / "camp"
    proc = subprocess.Popen([sys.executable, "-m", "gcs.campaign", "circle", "--seeds", "1-3", *SHORT,
                             "--workers", "1", "--out", str(out)], cwd=REPO, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    started.append(proc)
    deadline = time.monotonic() + 90.0
    while not list((out / "rows").glob("*.parquet")) if (out / "rows").is_dir() else True:
        assert proc.poll() is None and time.monotonic() < deadline, "the first run never finished"
        time.sleep(0.05)
    workers = _worker_processes(psutil.Process(proc.pid))
    assert len(workers) == 1
    killed = workers[0].pid
    os.kill(killed, signal.SIGKILL)
    stdout, stderr = proc.communicate(timeout=90.0)
    assert proc.returncode == 0, stderr
    rows = read_rows(out)
    assert sorted(r["seed"] for r in rows) == [1, 2, 3] and all(r["error"] is None for r in rows)
    pids = [r["worker"].rsplit(":", 1)[1] for r in rows]
    assert str(killed) in pids and any(pid != str(killed) for pid in pids), "a new worker ran what was left"
    assert not psutil.pid_exists(killed) or psutil.Process(killed).status() == psutil.STATUS_ZOMBIE


@pytest.mark.integration
def test_ctrl_c_closes_the_cluster_and_keeps_the_rows(tmp_path: Path, started: list[subprocess.Popen]) -> None:
    out = tmp_path / "camp"
    proc = subprocess.Popen([sys.executable, "-m", "gcs.campaign", "circle", "--seeds", "1-4", *SHORT,
                             "--workers", "1", "--out", str(out)], cwd=REPO, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    started.append(proc)
    deadline = time.monotonic() + 90.0
    while not list((out / "rows").glob("*.parquet")) if (out / "rows").is_dir() else True:
        assert proc.poll() is None and time.monotonic() < deadline, "the first run never finished"
        time.sleep(0.05)
    children = psutil.Process(proc.pid).children(recursive=True)
    os.killpg(proc.pid, signal.SIGINT)
    _, stderr = proc.communicate(timeout=60.0)
    assert proc.returncode == 130
    assert "interrupted; " in stderr and "run the same command to resume" in stderr
    kept = read_rows(out)
    assert 1 <= len(kept) < 4 and all(r["error"] is None for r in kept)
    _, alive = psutil.wait_procs(children, timeout=10.0)
    assert not alive, "every worker process is stopped"


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


@pytest.mark.integration
def test_runs_on_a_separately_started_scheduler_and_worker(tmp_path: Path, started: list[subprocess.Popen]) -> None:
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    logs = tmp_path / "logs"
    logs.mkdir()
    for name, args in (("scheduler", ["scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"]),
                       ("worker", ["worker", address, "--nworkers", "1", "--nthreads", "1", "--no-dashboard",
                                   "--host", "127.0.0.1"])):
        with (logs / f"{name}.log").open("wb") as log:
            started.append(subprocess.Popen([str(DASK), *args], cwd=REPO, stdout=log, stderr=subprocess.STDOUT,
                                            start_new_session=True))
    out = tmp_path / "camp"
    done = campaign("circle", "--seeds", "1-2", *SHORT, "--scheduler", address, "--out", str(out))
    assert done.returncode == 0, done.stderr + (logs / "worker.log").read_text()
    assert f"scheduler {address}" in done.stdout
    rows = read_rows(out)
    assert sorted(r["seed"] for r in rows) == [1, 2] and all(r["error"] is None for r in rows)
    assert all(p.poll() is None for p in started), "the campaign must leave an external cluster running"
