"""What an agent reports when it exits, read back from its log (``<out>/agent_<id>.log``).

An agent counts the relayed copies it refused as impossible in its own onboard state and writes the count in its
last log line (``vehicle_agents.__main__``: ``vehicle 3 exits with 0: ...; relayed copies refused: 2``), with what
its perception cost per frame (``(perception 0.61 / 0.93 ms CPU per frame, p50 / p95)``). The ground station stops
its agents before it writes the outputs, so by then every agent that exited normally has written that line; one
that was killed has not, and its figures stay unknown (None), never guessed.
"""

from __future__ import annotations

import re
from pathlib import Path

_EXIT_LINE = re.compile(r"vehicle (\d+) exits with -?\d+: .*relayed copies refused: (\d+)")
_PERCEPTION = re.compile(r"vehicle (\d+) exits with -?\d+: .*\(perception (\S+) / (\S+) ms CPU per frame, p50 / p95\)")


def refused_copies_in_log(text: str, vehicle_id: int) -> int | None:
    """The relayed copies ``vehicle_id`` refused, from the last exit line of its log text (None: no such line)."""
    count = None
    for match in _EXIT_LINE.finditer(text):
        if int(match.group(1)) == vehicle_id:
            count = int(match.group(2))
    return count


def agent_refused_copies(log_path: Path, vehicle_id: int) -> int | None:
    """The count in an agent's log file (None when the file or its exit line is missing)."""
    try:
        text = log_path.read_text(errors="replace")
    except OSError:
        return None
    return refused_copies_in_log(text, vehicle_id)


def perception_cpu_in_log(text: str, vehicle_id: int) -> tuple[float, float] | None:
    """(p50, p95) of ``vehicle_id``'s perception CPU per frame [ms] from the last exit line of its log text (NaN
    when it perceived no frame; None: no such line)."""
    found = None
    for match in _PERCEPTION.finditer(text):
        if int(match.group(1)) == vehicle_id:
            found = (float(match.group(2)), float(match.group(3)))
    return found
