"""Who a drone hears: the newest state per neighbour, what departed, and what is too old to act on (pure).

One rule for both engines (it used to be three control periods of arrival time in an agent and
``neighbour_timeout_s`` of message age in lockstep): a neighbour counts while its newest message is at most
``neighbour_timeout_s`` old by the sender's own time stamp, the age a control law corrects for (the radio's latency
counts, not when the message happened to arrive). A message with ``FLAG_LEAVING``, or a liveliness token that
vanished, removes its sender at once and until its token reappears. Newest sequence number wins, except that a
sender whose time stamp jumped past the timeout restarted (its counter began again).
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
        if msg.flags & FLAG_LEAVING:
            departed = departed | {sender}
            table.pop(sender, None)
            continue
        current = table.get(sender)
        if msg.t_s >= oldest_t_s and (current is None or msg.seq > current.seq or msg.t_s > current.t_s + timeout_s):
            table[sender] = msg
    return table, departed
