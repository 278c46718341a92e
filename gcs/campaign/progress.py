"""The campaign's live progress: done, running, failed and an ETA, as a rich bar on a terminal, plain lines elsewhere."""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from typing import TextIO

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn


@dataclass(frozen=True)
class Counts:
    """Where the campaign stands: runs of this invocation (``skipped`` were done by an earlier one)."""

    total: int
    done: int
    failed: int
    running: int
    skipped: int = 0


def eta_s(counts: Counts, elapsed_s: float) -> float | None:
    """Seconds left at the pace so far (runs finished per second of this invocation); None before the first."""
    if counts.done <= 0:
        return None
    return (counts.total - counts.done) * elapsed_s / counts.done


def format_duration(seconds: float | None) -> str:
    if seconds is None:
        return "?"
    seconds = max(0, round(seconds))
    hours, rest = divmod(seconds, 3600)
    minutes, secs = divmod(rest, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"


def status_text(counts: Counts, elapsed_s: float) -> str:
    """``12/40 done, 2 running, 1 failed, ETA 3:10`` (plus runs skipped as already done)."""
    skipped = f", {counts.skipped} already done" if counts.skipped else ""
    return (f"{counts.done}/{counts.total} done, {counts.running} running, {counts.failed} failed, "
            f"ETA {format_duration(eta_s(counts, elapsed_s))}{skipped}")


class ProgressView:
    """Shows :class:`Counts` as they change; a context manager so the bar is always closed."""

    PLAIN_PERIOD_S = 10.0

    def __init__(self, total: int, skipped: int, stream: TextIO | None = None, live: bool | None = None) -> None:
        self.stream = stream or sys.stdout
        self.live = self.stream.isatty() if live is None else live
        self.start_s = time.monotonic()
        self.counts = Counts(total, 0, 0, 0, skipped)
        self._last_line_s = -1e9
        self._last_text = ""
        self._progress: Progress | None = None
        self._task = None

    def __enter__(self) -> ProgressView:
        if self.live:
            self._progress = Progress(
                TextColumn("[bold]campaign"), BarColumn(), MofNCompleteColumn(), TextColumn("{task.description}"),
                TimeElapsedColumn(), console=Console(file=self.stream), transient=False)
            self._progress.start()
            self._task = self._progress.add_task("", total=self.counts.total)
        return self

    def update(self, counts: Counts, message: str | None = None) -> None:
        """New counts; ``message`` (a finished run) is printed as its own line above the bar."""
        self.counts = counts
        elapsed_s = time.monotonic() - self.start_s
        text = status_text(counts, elapsed_s)
        if self._progress is not None and self._task is not None:
            if message:
                self._progress.console.print(message, markup=False, highlight=False)
            eta = format_duration(eta_s(counts, elapsed_s))
            self._progress.update(self._task, completed=counts.done,
                                  description=f"{counts.running} running, {counts.failed} failed, ETA {eta}")
            return
        now = time.monotonic()
        if message:
            print(message, file=self.stream, flush=True)
        if message or (text != self._last_text and now - self._last_line_s >= self.PLAIN_PERIOD_S):
            print(f"campaign: {text}", file=self.stream, flush=True)
            self._last_line_s = now
            self._last_text = text

    def __exit__(self, *exc: object) -> None:
        if self._progress is not None:
            self._progress.stop()
