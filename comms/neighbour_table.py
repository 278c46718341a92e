"""Who a drone (or the ground station) currently hears: newest state per neighbour, staleness and deaths.

The control laws (paper eqs 6-10) sum over the neighbours a drone hears; a neighbour that died or went quiet must
drop out of those sums, or a drone keeps being repelled by (or tracking) a ghost. Two signals remove one:

* liveliness: the neighbour's process exited or was killed (its Zenoh token vanished) -> ``dead`` at once;
* staleness: nothing heard for ``stale_periods`` (3) broadcast periods -> ``stale`` (out of range, radio loss, or
  a hung process). A stale neighbour comes back (``rejoined``) with its next message.

Pure bookkeeping: no clock, no sockets. Times are the owner's clock (``now_s``), e.g. the mission clock; works
without liveliness (the lockstep engine), then only staleness applies.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from comms.messages import FLAG_LEAVING, NeighbourState

EventKind = Literal["joined", "rejoined", "stale", "dead", "left", "alive"]


@dataclass(frozen=True)
class Neighbour:
    """A neighbour's newest state and when it was heard [s, owner's clock]; ``age_s(now)`` is how old the
    information is by the sender's source time (mission clock shared by all vehicles)."""

    state: NeighbourState
    heard_t_s: float

    @property
    def vehicle_id(self) -> int:
        return self.state.sender_id

    def age_s(self, now_s: float) -> float:
        return max(0.0, now_s - self.state.t_s)


@dataclass(frozen=True)
class NeighbourEvent:
    """A change in the table, for logs and the ground station's report (``PeerEvent`` on the wire)."""

    vehicle_id: int
    event: EventKind
    t_s: float


class NeighbourTable:
    """Newest-seq-wins table of neighbour states with staleness (``stale_periods`` x ``period_s``) and deaths."""

    def __init__(self, own_id: int | None = None, period_s: float = 0.05, stale_periods: float = 3.0) -> None:
        if period_s <= 0 or stale_periods <= 0:
            raise ValueError("period_s and stale_periods must be > 0")
        self.own_id = own_id
        self.stale_after_s = period_s * stale_periods
        self._fresh: dict[int, Neighbour] = {}
        self._stale: dict[int, Neighbour] = {}
        self._dead: set[int] = set()
        self._events: list[NeighbourEvent] = []
        self.ignored_old = 0
        self.ignored_dead = 0

    # ---- inputs
    def heard(self, state: NeighbourState, now_s: float) -> bool:
        """Record a received state; False if ignored (own, older seq, or from a vehicle known dead/left)."""
        vid = state.sender_id
        if vid == self.own_id:
            return False
        if vid in self._dead:
            self.ignored_dead += 1
            return False
        previous = self._fresh.get(vid) or self._stale.get(vid)
        if previous is not None and state.seq <= previous.state.seq:
            restarted = state.t_s > previous.state.t_s + self.stale_after_s
            if not restarted:
                self.ignored_old += 1
                return False
        if state.flags & FLAG_LEAVING:
            self._remove(vid)
            self._dead.add(vid)
            self._events.append(NeighbourEvent(vid, "left", now_s))
            return True
        if vid in self._stale:
            del self._stale[vid]
            self._events.append(NeighbourEvent(vid, "rejoined", now_s))
        elif previous is None:
            self._events.append(NeighbourEvent(vid, "joined", now_s))
        self._fresh[vid] = Neighbour(state, now_s)
        return True

    def liveliness(self, vehicle_id: int, alive: bool, now_s: float) -> None:
        """A liveliness token appeared (``alive``) or vanished: death removes the neighbour at once."""
        if vehicle_id == self.own_id:
            return
        if alive:
            if vehicle_id in self._dead:
                self._dead.discard(vehicle_id)
                self._events.append(NeighbourEvent(vehicle_id, "alive", now_s))
            return
        if vehicle_id not in self._dead:
            self._remove(vehicle_id)
            self._dead.add(vehicle_id)
            self._events.append(NeighbourEvent(vehicle_id, "dead", now_s))

    def expire(self, now_s: float) -> list[NeighbourEvent]:
        """Move neighbours not heard for ``stale_after_s`` to stale; returns the new ``stale`` events."""
        limit = now_s - self.stale_after_s
        gone = [vid for vid, n in self._fresh.items() if n.heard_t_s < limit]
        new_events = []
        for vid in gone:
            self._stale[vid] = self._fresh.pop(vid)
            event = NeighbourEvent(vid, "stale", now_s)
            self._events.append(event)
            new_events.append(event)
        return new_events

    # ---- outputs
    def neighbours(self, now_s: float | None = None) -> list[Neighbour]:
        """Fresh neighbours sorted by id (call ``expire(now_s)`` first, or pass ``now_s`` to do it here)."""
        if now_s is not None:
            self.expire(now_s)
        return [self._fresh[k] for k in sorted(self._fresh)]

    def get(self, vehicle_id: int) -> Neighbour | None:
        return self._fresh.get(vehicle_id)

    @property
    def fresh_ids(self) -> list[int]:
        return sorted(self._fresh)

    @property
    def stale_ids(self) -> list[int]:
        return sorted(self._stale)

    @property
    def dead_ids(self) -> list[int]:
        return sorted(self._dead)

    def take_events(self) -> list[NeighbourEvent]:
        """Events since the last call (joined, rejoined, stale, dead, left, alive), oldest first."""
        events, self._events = self._events, []
        return events

    def _remove(self, vehicle_id: int) -> None:
        self._fresh.pop(vehicle_id, None)
        self._stale.pop(vehicle_id, None)
