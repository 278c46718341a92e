"""Event-log lines as the ground station writes them, classified for the map's alerts."""

from __future__ import annotations

import pytest

from comms.gcs_status import EventKind
from gcs.dashboard.event_kinds import classify


@pytest.mark.parametrize(("text", "kind", "vehicle", "active"), [
    ("vehicle 4 lost: no heartbeat on the GCS link for 2 s", EventKind.VEHICLE_LOST, 4, True),
    ("vehicle 4: heartbeat back on the GCS link", EventKind.VEHICLE_LOST, 4, False),
    ("agent 7 lost: its liveliness token is gone", EventKind.AGENT_LOST, 7, True),
    ("agent 7 exited with code -9", EventKind.AGENT_LOST, 7, True),
    ("vehicle 3 says: Failsafe: offboard lost, AUTO_LOITER", EventKind.FAILSAFE, 3, True),
    ("ring gap between vehicles 2 and 4: 31.0 m, over 1.5x the ideal 12.0 m", EventKind.RING_GAP, 2, True),
    ("ring gap between vehicles 2 and 4 closed", EventKind.RING_GAP, 2, False),
    ("edge unseen: 12.0 m of the caged polygon's edge under no camera footprint (longest stretch 8.0 m)",
     EventKind.UNCOVERED_EDGE, None, True),
    ("edge seen again: every part of the caged polygon's edge is under a camera footprint",
     EventKind.UNCOVERED_EDGE, None, False),
    ("operator hold requested from 127.0.0.1:5000: standing order hold", EventKind.OPERATOR, None, True),
    ("vehicle 3 says: Takeoff detected", EventKind.INFO, None, True),
    ("vehicle 3: armed, mode OFFBOARD", EventKind.INFO, None, True),
])
def test_classify(text: str, kind: EventKind, vehicle: int | None, active: bool) -> None:
    got = classify(text)
    assert (got.kind, got.vehicle_id, got.active) == (kind, vehicle, active)
