"""Which event-log lines are alerts (pure): the ground station writes one plain line per event; the map needs to
know which ones are a vehicle lost, an agent gone or a failsafe taken, and which vehicle they are about.

The patterns match the lines the ground station and its MAVLink watcher write (``vehicle 3 lost: ...``,
``agent 3 lost: ...``, ``agent 3 exited with code -9``, ``vehicle 3 says: Failsafe: offboard lost, ...``);
``vehicle 3: heartbeat back ...`` clears a lost vehicle. The geometric alerts (:mod:`gcs.dashboard.gcs_link`) are
written as ``ring gap between vehicles 2 and 4: ...`` / ``... closed`` and ``edge unseen: ...`` / ``edge seen
again: ...``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from comms.gcs_status import EventKind


@dataclass(frozen=True)
class Classified:
    kind: EventKind
    vehicle_id: int | None = None
    active: bool = True


_PATTERNS: tuple[tuple[re.Pattern[str], EventKind, bool], ...] = (
    (re.compile(r"^vehicle (\d+) lost\b"), EventKind.VEHICLE_LOST, True),
    (re.compile(r"^vehicle (\d+): heartbeat back\b"), EventKind.VEHICLE_LOST, False),
    (re.compile(r"^agent (\d+) (?:lost\b|exited with code)"), EventKind.AGENT_LOST, True),
    (re.compile(r"^vehicle (\d+) says: failsafe", re.IGNORECASE), EventKind.FAILSAFE, True),
    (re.compile(r"^ring gap between vehicles (\d+) and \d+:"), EventKind.RING_GAP, True),
    (re.compile(r"^ring gap between vehicles (\d+) and \d+ closed"), EventKind.RING_GAP, False),
    (re.compile(r"^edge unseen:"), EventKind.UNCOVERED_EDGE, True),
    (re.compile(r"^edge seen again\b"), EventKind.UNCOVERED_EDGE, False),
    (re.compile(r"^operator\b"), EventKind.OPERATOR, True),
)


def classify(text: str) -> Classified:
    """The kind of an event-log line and the vehicle it names; INFO for everything that is not an alert."""
    for pattern, kind, active in _PATTERNS:
        match = pattern.match(text)
        if match:
            vehicle = int(match.group(1)) if match.groups() else None
            return Classified(kind, vehicle, active)
    return Classified(EventKind.INFO)
