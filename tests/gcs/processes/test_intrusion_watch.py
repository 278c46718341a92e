"""The ground station's tally of rejected messages: first one at once, then at most one report a second (pure)."""

from __future__ import annotations

from comms.signing import Rejection
from comms.swarm_link import RejectedMessage
from gcs.processes.intrusion_watch import IntrusionTally, event_text, source_text

COMMAND = "floodwatch/m/gcs/command"
STATE_3 = "floodwatch/m/uav/3/state"


def test_first_attempt_is_due_at_once_then_grouped_per_second() -> None:
    tally = IntrusionTally(report_period_s=1.0)
    tally.observe(RejectedMessage(COMMAND, Rejection.UNSIGNED, None))
    assert tally.due(10.0) == [(Rejection.UNSIGNED, COMMAND, "unknown", 1, 1)]
    for _ in range(5):
        tally.observe(RejectedMessage(COMMAND, Rejection.UNSIGNED, None))
    tally.observe(RejectedMessage(STATE_3, Rejection.WRONG_SENDER, 5))
    assert tally.due(10.5) == [(Rejection.WRONG_SENDER, STATE_3, "5", 1, 1)], "another kind is reported at once"
    assert tally.due(11.0) == [(Rejection.UNSIGNED, COMMAND, "unknown", 5, 6)], "the flood is counted in full"
    assert tally.due(20.0) == [] and tally.total == 7


def test_event_lines_name_what_happened() -> None:
    assert "did not sign" in event_text(Rejection.UNSIGNED, COMMAND, "unknown", 1, 1, COMMAND)
    assert "vehicle 5 speaking for another id on " + STATE_3 in event_text(Rejection.WRONG_SENDER, STATE_3, "5", 1, 1,
                                                                            COMMAND)
    assert "replayed" in event_text(Rejection.REPLAYED, COMMAND, "gcs", 2, 3, COMMAND)


def test_the_sender_is_named_when_zenoh_gives_it() -> None:
    tally = IntrusionTally()
    tally.observe(RejectedMessage(COMMAND, Rejection.BAD_TAG, 0xFFFF_FFFF, source="ab12"))
    assert tally.sources[(Rejection.BAD_TAG, COMMAND, "gcs")] == "ab12"
    assert source_text("ab12", "tcp/127.0.0.1:40000") == "sent by Zenoh session ab12 at tcp/127.0.0.1:40000"
    assert source_text("", "") == "sender address not given by Zenoh"
