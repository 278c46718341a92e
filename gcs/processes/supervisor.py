"""Starts and stops the mission's child processes so that none outlives the ground station.

Each child runs in its own process group (so a Ctrl-C in the terminal reaches only the ground station, which then
stops the children in order) and, on Linux, asks the kernel to send it SIGTERM when its parent dies, so even a
kill -9 of the ground station leaves no orphans. :meth:`Supervisor.stop_all` sends SIGTERM to every group, waits,
then SIGKILLs what is left; it runs on every exit path (the supervisor is a context manager).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import IO

_CHILD_BOOT = """
import ctypes, os, runpy, sys
parent, niceness = int(sys.argv[1]), int(sys.argv[2])
try:
    ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, 15)  # PR_SET_PDEATHSIG, SIGTERM
except OSError:
    pass
if os.getppid() != parent:
    sys.exit(143)
if niceness:
    os.nice(niceness)
    try:
        with open("/proc/self/autogroup", "w") as autogroup:
            autogroup.write(str(niceness))
    except OSError:
        pass
sys.argv = sys.argv[3:]
runpy.run_module(sys.argv[0], run_name="__main__", alter_sys=True)
"""
"""What a child runs first, in its own interpreter, before its module (as ``python -m`` would run it): ask the
kernel for SIGTERM when the parent dies (``prctl(PR_SET_PDEATHSIG)``; exit at once if the parent is already gone),
then lower the CPU priority by ``niceness``. The child runs in its own session, and Linux schedules sessions as
autogroups that share the CPU equally whatever their processes' nice values; so the autogroup's nice is lowered too
(``/proc/self/autogroup``), or a busy machine would give each of 13 agents as much CPU as the simulator.

This runs after ``exec``, never between ``fork`` and ``exec`` (a ``preexec_fn``): the ground station has Zenoh's
threads calling into Python, and a child forked while one of them holds the interpreter's thread-state lock would
block forever in ``PyOS_AfterFork_Child`` before running anything."""


def child_command(module_args: list[str], niceness: int = 0, parent_pid: int | None = None) -> list[str]:
    """The command line of a child running ``python -m <module_args...>`` after :data:`_CHILD_BOOT`."""
    parent = os.getpid() if parent_pid is None else parent_pid
    return [sys.executable, "-c", _CHILD_BOOT, str(parent), str(int(niceness)), *module_args]


@dataclass
class Child:
    name: str
    process: subprocess.Popen[bytes]
    log_path: Path

    @property
    def pid(self) -> int:
        return self.process.pid

    def exit_code(self) -> int | None:
        return self.process.poll()

    def log_tail(self, lines: int = 5) -> str:
        """The last lines the child wrote (stdout and stderr), for one clear error message."""
        try:
            text = self.log_path.read_text(errors="replace").strip().splitlines()
        except OSError:
            return ""
        return " | ".join(text[-lines:])


class Supervisor:
    """Owns the child processes of one mission run."""

    def __init__(self, log_dir: Path) -> None:
        self.children: list[Child] = []
        self._log_dir = log_dir
        self._logs: list[IO[bytes]] = []

    def start(self, name: str, module_args: list[str], env: dict[str, str] | None = None, niceness: int = 0) -> Child:
        """Start ``python -m <module_args...>`` with this interpreter; its output goes to ``<log_dir>/<name>.log``.

        ``niceness`` > 0 lowers the child's CPU priority (the agents run at a lower priority than the simulator, so
        on a busy machine the simulated world keeps its clock and the agents are the ones that fall behind, as a
        slow companion computer would)."""
        log_path = self._log_dir / f"{name}.log"
        log = open(log_path, "ab")  # noqa: SIM115 - closed in stop_all
        self._logs.append(log)
        child_env = dict(os.environ)
        child_env.setdefault("PYTHONUNBUFFERED", "1")
        if env:
            child_env.update(env)
        process = subprocess.Popen(
            child_command(module_args, niceness),
            stdout=log,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            start_new_session=True,
            env=child_env,
        )
        child = Child(name, process, log_path)
        self.children.append(child)
        return child

    def lower_priority(self, child: Child, niceness: int) -> bool:
        """Set a running child's session (autogroup) nice, what Linux weighs sessions by; False when the child is
        gone or the kernel refuses (raising it needs no privilege)."""
        try:
            Path(f"/proc/{child.pid}/autogroup").write_text(str(int(niceness)))
        except OSError:
            return False
        return True

    def kill(self, child: Child, sig: int = signal.SIGKILL) -> None:
        """Signal one child's whole process group (fault injection and shutdown)."""
        try:
            os.killpg(child.pid, sig)
        except ProcessLookupError:
            pass

    def stop_all(self, grace_s: float = 3.0) -> None:
        """SIGTERM every child's group, wait up to ``grace_s``, SIGKILL the rest, reap everything. Idempotent."""
        for child in reversed(self.children):
            if child.exit_code() is None:
                self.kill(child, signal.SIGTERM)
        deadline = time.monotonic() + grace_s
        for child in self.children:
            remaining = max(0.0, deadline - time.monotonic())
            try:
                child.process.wait(timeout=remaining)
            except subprocess.TimeoutExpired:
                pass
        for child in self.children:
            # Kill the group even if the leader is gone: a grandchild may still hold it.
            self.kill(child, signal.SIGKILL)
            try:
                child.process.wait(timeout=2.0)
            except subprocess.TimeoutExpired:
                pass
        for log in self._logs:
            log.close()
        self._logs.clear()

    def __enter__(self) -> "Supervisor":
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop_all()
