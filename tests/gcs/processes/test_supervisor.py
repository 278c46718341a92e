"""The supervisor's children: niced, in their own session, dying with their parent, and started safely while other
threads of the parent create and drop Python thread states (as Zenoh's callback threads do in the ground station)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

from gcs.processes.supervisor import Supervisor, child_command

_REPORT = "import os, sys; print(os.getpriority(os.PRIO_PROCESS, 0), os.getsid(0) == os.getpid(), sys.argv[1:])"


def _module(tmp_path: Path, name: str, body: str) -> None:
    (tmp_path / f"{name}.py").write_text(body)


def test_child_runs_its_module_niced_in_its_own_session(tmp_path: Path, monkeypatch) -> None:
    _module(tmp_path, "report_child", _REPORT)
    monkeypatch.chdir(tmp_path)
    base = os.getpriority(os.PRIO_PROCESS, 0)
    with_supervisor = Supervisor(tmp_path)
    try:
        child = with_supervisor.start("report", ["report_child", "--flag", "x"], niceness=3)
        assert child.process.wait(timeout=20) == 0
    finally:
        with_supervisor.stop_all()
    nice, own_session, argv = (tmp_path / "report.log").read_text().split(" ", 2)
    assert int(nice) == min(19, base + 3)
    assert own_session == "True"
    assert argv.strip() == "['--flag', 'x']"


def test_child_exits_when_its_parent_is_gone(tmp_path: Path) -> None:
    _module(tmp_path, "sleeper", "import time; time.sleep(60)")
    parent = subprocess.Popen([sys.executable, "-c", (
        "import subprocess, sys, time\n"
        "from gcs.processes.supervisor import child_command\n"
        "p = subprocess.Popen(child_command(['sleeper']), cwd=sys.argv[1])\n"
        "print(p.pid, flush=True)\n"
        "time.sleep(60)\n"), str(tmp_path)], stdout=subprocess.PIPE, text=True)
    assert parent.stdout is not None
    child_pid = int(parent.stdout.readline())
    time.sleep(1.5)  # the child has set its death signal
    parent.send_signal(signal.SIGKILL)
    parent.wait(timeout=10)
    deadline = time.monotonic() + 10.0
    while time.monotonic() < deadline:
        try:
            os.kill(child_pid, 0)
        except ProcessLookupError:
            return
        time.sleep(0.1)
    os.kill(child_pid, signal.SIGKILL)
    raise AssertionError("the child outlived its parent")


def test_child_of_a_dead_parent_never_starts(tmp_path: Path) -> None:
    _module(tmp_path, "report_child", _REPORT)
    done = subprocess.run(child_command(["report_child"], parent_pid=1 if os.getppid() != 1 else 2),
                          cwd=tmp_path, capture_output=True, text=True, timeout=20)
    assert done.returncode == 143
    assert done.stdout == ""


def test_many_children_start_while_threads_churn(tmp_path: Path, monkeypatch) -> None:
    _module(tmp_path, "quick", "pass")
    monkeypatch.chdir(tmp_path)
    stop = threading.Event()

    def churn() -> None:
        while not stop.is_set():
            threading.Thread(target=lambda: None).start()

    churners = [threading.Thread(target=churn, daemon=True) for _ in range(3)]
    for thread in churners:
        thread.start()
    supervisor = Supervisor(tmp_path)
    try:
        children = [supervisor.start(f"quick_{i}", ["quick"]) for i in range(30)]
        assert [c.process.wait(timeout=30) for c in children] == [0] * 30
    finally:
        stop.set()
        supervisor.stop_all()


def test_a_running_child_is_lowered_to_a_new_nice(tmp_path: Path, monkeypatch) -> None:
    _module(tmp_path, "sleeper", "import time; time.sleep(30)")
    monkeypatch.chdir(tmp_path)
    supervisor = Supervisor(tmp_path)
    try:
        child = supervisor.start("sleeper", ["sleeper"], niceness=5)
        deadline = time.monotonic() + 10.0
        while "nice 5" not in Path(f"/proc/{child.pid}/autogroup").read_text() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert supervisor.lower_priority(child, 12)
        assert Path(f"/proc/{child.pid}/autogroup").read_text().split()[-1] == "12"
    finally:
        supervisor.stop_all()
    assert not supervisor.lower_priority(child, 13)
