"""Who a drone hears: the newest state per neighbour, what departed, and what is too old to act on (pure).

One rule for both engines (it used to be three control periods of arrival time in an agent and
``neighbour_timeout_s`` of message age in lockstep): a neighbour counts while its newest message is at most
``neighbour_timeout_s`` old by the sender's own time stamp, the age a control law corrects for (the radio's latency
counts, not when the message happened to arrive). A message with ``FLAG_LEAVING``, or a liveliness token that
vanished, removes its sender at once and until its token reappears. Newest sequence number wins, except that a
sender whose time stamp jumped past the timeout restarted (its counter began again), and that an entry filed from a
relayed copy gives way to the origin's own message and otherwise to a copy with a newer origin time stamp.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from comms.messages import FLAG_LEAVING, HeardState


@dataclass(frozen=True)
class Inbox:
    """What reached one drone since its previous step: decoded states, and liveliness changes (vehicle ids)."""

    states: Sequence[HeardState] = ()
    departed_ids: Sequence[int] = ()
    returned_ids: Sequence[int] = ()


EMPTY_INBOX = Inbox()


def heard_after(
    heard: Mapping[int, HeardState],
    departed: frozenset[int],
    inbox: Inbox,
    own_id: int,
    t_s: float,
    timeout_s: float,
) -> tuple[Mapping[int, HeardState], frozenset[int]]:
    """The table after ``inbox`` at mission time ``t_s`` (a new mapping; the one given is left as it was)."""
    if inbox.departed_ids or inbox.returned_ids:
        departed = (departed - frozenset(inbox.returned_ids)) | frozenset(inbox.departed_ids)
    oldest_t_s = t_s - timeout_s
    table = {vid: msg for vid, msg in heard.items() if vid not in departed and msg.t_s >= oldest_t_s}
    for msg in inbox.states:
        sender = msg.sender_id
        if sender == own_id or sender in departed:
            continue
        current = table.get(sender)
        if current is msg:  # the same copy again, through another carrier: already filed
            continue
        if msg.flags & FLAG_LEAVING:
            departed = departed | {sender}
            table.pop(sender, None)
            continue
        if msg.t_s >= oldest_t_s and (current is None or replaces(msg, current, timeout_s)):
            table[sender] = msg
    return table, departed


def replaces(msg: HeardState, current: HeardState, timeout_s: float) -> bool:
    """Whether ``msg`` replaces the entry ``current`` of the same sender. Between the origin's own messages the
    newest ``seq`` wins (or a time stamp past the timeout: a restart); the origin's own message replaces a relayed
    copy, and a copy replaces a copy when its origin time stamp is newer (for one origin both orders agree, but a
    copy's ``seq`` is its carrier's word only: :mod:`vehicle_agents.core.relay_admission`)."""
    msg_relayed, current_relayed = getattr(msg, "hops", 0) > 0, getattr(current, "hops", 0) > 0
    if current_relayed:
        return not msg_relayed or msg.t_s > current.t_s
    return msg.seq > current.seq or msg.t_s > current.t_s + timeout_s
