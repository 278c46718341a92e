"""Which relayed copies a receiver may file: the check that keeps a key holder from silencing another drone (pure).

A relayed copy is signed by its carrier, not by its origin (docs/COMMS.md, "Relay and the mission key"): any drone
holding the mission key can put a copy of another drone's state in its own message. Filed newest-``seq``-wins, one
forged copy with a huge ``seq`` would make every receiver ignore the origin's genuine messages. Three rules close
that, and none of them ever refuses what an honest fleet sends:

* a copy whose origin time stamp lies ahead of the receiver's clock by more than one state period is dropped: an
  honest copy was heard by its relayer before it was passed on, so it is never younger than the receiver's now
  (the period allows for agents' clocks that tick a little apart);
* a copy's ``seq`` may run ahead of the entry the receiver holds for that origin by at most what the origin could
  have sent in between, at its state rate (``state_rate_hz``, one state per control period) with half again as
  much slack plus two, for a late tick;
* in the neighbour table (:func:`vehicle_agents.core.neighbours.heard_after`) the origin's own message always
  replaces an entry filed from a copy, and copies are compared with what is filed by their origin's time stamp.

For one honest origin ``seq`` and time stamp grow together, so the last rule files exactly what newest-``seq``-wins
filed; what remains open is a key holder injecting *plausible* states for drones its victims hear only through
relays, which only per-vehicle signatures close (docs/COMMS.md).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from enum import Enum

from comms.messages import HeardState
from vehicle_agents.core.neighbours import replaces

SEQ_RATE_SLACK = 1.5
SEQ_EXTRA = 2


class CopyVerdict(Enum):
    """What a receiver does with one relayed copy."""

    FILE = "file"
    FUTURE = "future"  # the origin's time stamp is ahead of the receiver's clock
    SEQ_AHEAD = "seq_ahead"  # the seq runs ahead of the filed entry by more than the origin could have sent


def hops_of(msg: HeardState) -> int:
    """How many relays a state went through (0: heard from its origin; the control-only decoding has no relays)."""
    return getattr(msg, "hops", 0)


def max_seq_advance(elapsed_s: float, state_rate_hz: float) -> int:
    """The largest ``seq`` increase an honest origin can make in ``elapsed_s`` of its own time stamps."""
    return math.ceil(max(0.0, elapsed_s) * state_rate_hz * SEQ_RATE_SLACK) + SEQ_EXTRA


def copy_verdict(copy: HeardState, filed: HeardState | None, t_s: float, state_rate_hz: float) -> CopyVerdict:
    """The verdict on one relayed copy at the receiver's mission time ``t_s``, given the entry filed for its origin."""
    if copy.t_s > t_s + 1.0 / state_rate_hz:
        return CopyVerdict.FUTURE
    if filed is not None and copy.seq - filed.seq > max_seq_advance(copy.t_s - filed.t_s, state_rate_hz):
        return CopyVerdict.SEQ_AHEAD
    return CopyVerdict.FILE


def admitted(states: Sequence[HeardState], table: Mapping[int, HeardState], t_s: float,
             state_rate_hz: float) -> tuple[Sequence[HeardState], int]:
    """The inbox without the relayed copies refused by :func:`copy_verdict`, and how many were refused. Each copy
    is checked against what the table would hold for its origin at that point of the inbox (the origin's own
    message earlier in the same inbox counts); direct states pass untouched, and an inbox without refusals is
    returned as it was.

    Most copies a drone hears are not news: the origin's own message or a fresher copy came too, and every
    neighbour relays the same few origins for a few ticks. A copy (or the entry filed, met again) whose ``seq`` and
    time stamp are both at most the entry's, and not from the future, is settled at once: its ``seq`` does not run
    ahead, so it is filed, and it replaces nothing (:func:`~vehicle_agents.core.neighbours.replaces`)."""
    if state_rate_hz <= 0.0:
        return states, 0
    reference = dict(table)
    refused: set[int] = set()
    latest_t_s = t_s + 1.0 / state_rate_hz
    for i, msg in enumerate(states):
        current = reference.get(msg.sender_id)
        if current is not None and msg.seq <= current.seq and msg.t_s <= current.t_s and msg.t_s <= latest_t_s \
                and (current is msg or hops_of(msg) > 0):
            continue
        if hops_of(msg) > 0 and copy_verdict(msg, current, t_s, state_rate_hz) is not CopyVerdict.FILE:
            refused.add(i)
        elif current is None or replaces(msg, current, math.inf):
            reference[msg.sender_id] = msg
    if not refused:
        return states, 0
    return [m for i, m in enumerate(states) if i not in refused], len(refused)
