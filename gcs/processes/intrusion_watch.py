"""The ground station notices messages it did not expect: commands it did not sign, forged or replayed states.

Only the ground station commands the fleet, and it signs every command (:mod:`comms.signing`). It also listens on
the command key itself: anything there that fails its own check (no tag, a wrong tag, a replay of one of its own
commands) was put there by someone else. The states it hears through :class:`comms.swarm_link.SwarmLink` (audit
mode: every sample, none coalesced) are checked the same way; a valid tag from another vehicle than the key's is a
drone speaking for another id.

Each kind of attempt (reason, key, claimed sender) is reported at once the first time and then at most once per
``report_period_s`` with the count since, so a flood of forgeries is counted in full without flooding the log:
a line in events.log and the live view, and a :class:`~comms.messages.SecurityEvent` on the public events key.
Zenoh 1.x gives no sender address for a plain ``put`` (``Sample.source_info`` is empty unless the publisher sets
it); when a sample does carry one, the event names that Zenoh id and, when the hub has a link to it, its address.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from comms.keys import MissionKeys
from comms.messages import SecurityEvent, encode
from comms.signing import GROUND_STATION, MissionKey, Rejection, Signer, Verifier, sender_name
from comms.swarm_link import RejectedMessage, every_sample_unpacker, wall_clock_us
from comms.zenoh_session import ZenohSession

_WHAT = {
    Rejection.UNSIGNED: "without an authentication tag",
    Rejection.BAD_TAG: "with a wrong authentication tag",
    Rejection.WRONG_SENDER: "signed by another sender than the key's",
    Rejection.REPLAYED: "replayed (not newer than the newest accepted)",
    Rejection.OUT_OF_WINDOW: "with a timestamp outside the time window",
}


@dataclass
class IntrusionTally:
    """Counts rejected messages per (reason, key, claimed sender) and says when each is due to be reported (pure)."""

    report_period_s: float = 1.0
    totals: dict[tuple[Rejection, str, str], int] = field(default_factory=dict)
    sources: dict[tuple[Rejection, str, str], str] = field(default_factory=dict)
    """The newest publisher Zenoh id seen per kind (when samples carried one)."""
    _unreported: dict[tuple[Rejection, str, str], int] = field(default_factory=dict)
    _last_report_s: dict[tuple[Rejection, str, str], float] = field(default_factory=dict)

    def observe(self, rejected: RejectedMessage) -> None:
        kind = (rejected.reason, rejected.key, sender_name(rejected.claimed_sender))
        self.totals[kind] = self.totals.get(kind, 0) + 1
        self._unreported[kind] = self._unreported.get(kind, 0) + 1
        if rejected.source:
            self.sources[kind] = rejected.source

    def due(self, now_s: float) -> list[tuple[Rejection, str, str, int, int]]:
        """(reason, key, claimed sender, count since the last report, total) for every kind due at ``now_s``."""
        out = []
        for kind, count in list(self._unreported.items()):
            last = self._last_report_s.get(kind)
            if last is None or now_s - last >= self.report_period_s:
                out.append((*kind, count, self.totals[kind]))
                self._last_report_s[kind] = now_s
                del self._unreported[kind]
        return out

    @property
    def total(self) -> int:
        return sum(self.totals.values())


def source_text(zid: str, address: str) -> str:
    """How the event names the sender: its Zenoh id and address when known."""
    if not zid:
        return "sender address not given by Zenoh"
    return f"sent by Zenoh session {zid}" + (f" at {address}" if address else "")


def event_text(reason: Rejection, key: str, claimed: str, count: int, total: int, command_key: str,
               source: str = "sender address not given by Zenoh") -> str:
    """One events.log line for ``count`` rejected messages of one kind."""
    what = "command" if key == command_key else "state"
    if reason is Rejection.WRONG_SENDER:
        body = f"vehicle {claimed} speaking for another id on {key}"
    elif what == "command" and reason in (Rejection.UNSIGNED, Rejection.BAD_TAG):
        body = f"command on {key} that the ground station did not sign ({_WHAT[reason]}, claimed sender {claimed})"
    else:
        body = f"{what} on {key} {_WHAT[reason]} (claimed sender {claimed})"
    return f"SECURITY: {body}: dropped {count} (total {total}); {source}"


class IntrusionWatch:
    """Signs the ground station's commands and reports every message the mission's receivers must not trust."""

    def __init__(self, session: ZenohSession, keys: MissionKeys, key: MissionKey, log: Callable[[str], None],
                 mission_time_s: Callable[[], float], report_period_s: float = 1.0) -> None:
        self.session = session
        self.keys = keys
        self.signer = Signer(key, GROUND_STATION)
        self.commands = Verifier(key)
        self.tally = IntrusionTally(report_period_s)
        self._log = log
        self._mission_time_s = mission_time_s
        self._command_buf = session.subscribe(keys.command, unpack=every_sample_unpacker(), with_source=True)

    def sign_command(self, body: bytes) -> bytes:
        return self.signer.sign(body, wall_clock_us())

    def observe_states(self, rejected: list[RejectedMessage]) -> None:
        for r in rejected:
            self.tally.observe(r)

    def poll(self, now_wall_s: float) -> None:
        """Check what arrived on the command key, then log and publish every report due."""
        now_us = wall_clock_us()
        for item in self._command_buf.drain():
            if item.kind != "put":
                continue
            verdict = self.commands.check(item.payload, GROUND_STATION, now_us)
            if verdict.reason is not None:
                self.tally.observe(RejectedMessage(self.keys.command, verdict.reason, verdict.sender, item.source))
        for reason, key, claimed, count, total in self.tally.due(now_wall_s):
            zid = self.tally.sources.get((reason, key, claimed), "")
            address = self.session.address_of(zid) if zid else ""
            self._log(event_text(reason, key, claimed, count, total, self.keys.command, source_text(zid, address)))
            event = SecurityEvent(t_s=self._mission_time_s(), reason=reason.value, key=key, claimed_sender=claimed,
                                  count=count, total=total, source=f"{zid} {address}".strip())
            self.session.put_once(self.keys.events, encode(event))
