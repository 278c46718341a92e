"""Multi-hop knowledge: which heard states a drone passes on in its own message, and how a receiver unpacks them.

With a short radio range the leader at the centre of the flood hears no boundary drone, and the ground station at
the launch site hears only the nearest few, yet eq 9 needs the ring's positions and the rescue centre the whole
ring's edge points. Each drone therefore appends copies of states it heard (directly or relayed) to its own
broadcast. A copy keeps its origin's id, ``seq`` and time stamp, so a receiver files it exactly like a direct
message (newest ``seq`` per origin wins, the neighbour filter updates at the origin's time: its age counts), and
counts one more hop. Three limits keep the traffic bounded:

* a hop limit: a copy with ``hops == max_hops`` is not passed on;
* ageing: a state older than ``max_age_s`` by its origin's time stamp is not passed on (stale knowledge dies out
  after a few relays even on a lossless radio, since each relay adds at least one control period);
* a rate: copies ride on one message in ``relay_every`` (the onboard core decides, by the message's ``seq``);
* a byte budget per message: copies are added until the next would pass ``budget_bytes`` (encoded size), in an
  order that rotates with the relayer's own ``seq`` (a hash of origin id and seq), so a budget smaller than the
  table still passes every origin on in turn, the far ones (already relayed) as often as the direct ones.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import msgspec

from comms.messages import NeighbourState, encode

_GOLDEN = 0x9E3779B1


def _mix32(x: int) -> int:
    """A 32-bit integer hash (murmur3's finaliser): a different, well-spread order for every ``seq``."""
    x &= 0xFFFFFFFF
    x = ((x ^ (x >> 16)) * 0x85EBCA6B) & 0xFFFFFFFF
    x = ((x ^ (x >> 13)) * 0xC2B2AE35) & 0xFFFFFFFF
    return x ^ (x >> 16)


def relay_copies(table: Mapping[int, NeighbourState], own_id: int, t_s: float, seq: int, max_hops: int,
                 max_age_s: float, budget_bytes: int) -> list[NeighbourState]:
    """The copies one drone appends to its message ``seq`` at ``t_s`` (empty when relaying is off). Pure."""
    if max_hops <= 0 or budget_bytes <= 0:
        return []
    oldest_t_s = t_s - max_age_s
    candidates = [m for vid, m in table.items()
                  if vid != own_id and m.hops < max_hops and m.t_s >= oldest_t_s]
    candidates.sort(key=lambda m: _mix32(m.sender_id * _GOLDEN + seq))
    copies: list[NeighbourState] = []
    used = 0
    for message in candidates:
        copy = msgspec.structs.replace(message, hops=message.hops + 1, relayed=[])
        size = len(encode(copy))
        if used + size > budget_bytes:
            break
        copies.append(copy)
        used += size
    return copies


def unpacked(states: Sequence[NeighbourState]) -> Sequence[NeighbourState]:
    """The states of an inbox followed by every relayed copy they carry (the carriers are shared, not copied:
    in lockstep one decoded message reaches every receiver)."""
    if not any(m.relayed for m in states):
        return states
    return [*states, *(copy for message in states for copy in message.relayed)]
