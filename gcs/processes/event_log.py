"""The mission's event log: one line per event, written to ``events.log`` at once (a crash loses nothing).

Each line carries the wall-clock UTC time and the mission time, so it can be read beside the .tlogs. Listeners
(the live map's publisher) get every event as it is written; one that raises is dropped, never the event.
"""

from __future__ import annotations

import collections
import datetime as dt
from collections.abc import Callable
from pathlib import Path


class EventLog:
    def __init__(self, path: Path, mission_time_s: Callable[[], float], keep_last: int = 50) -> None:
        self._file = open(path, "a", encoding="utf-8", buffering=1)  # noqa: SIM115 - line-buffered, closed in close()
        self._mission_time_s = mission_time_s
        self.recent: collections.deque[str] = collections.deque(maxlen=keep_last)
        self.entries: list[tuple[float, str]] = []
        self.listeners: list[Callable[[float, str], None]] = []

    def __call__(self, text: str) -> None:
        t_s = self._mission_time_s()
        utc = dt.datetime.now(dt.timezone.utc).strftime("%H:%M:%S.%f")[:-3]
        line = f"{utc} t={t_s:7.2f}s {text}"
        self.recent.append(line)
        self.entries.append((t_s, text))
        if not self._file.closed:
            self._file.write(line + "\n")
        for listener in list(self.listeners):
            try:
                listener(t_s, text)
            except Exception:  # noqa: BLE001 - a broken listener must not cost the mission its log
                self.listeners.remove(listener)

    def close(self) -> None:
        self._file.close()
