"""Messages in flight: held until their delivery time, then released in time order.

The radio model (``comms.radio_model``) says *when* a packet arrives; something has to hold it until then. The
lockstep engine and the Zenoh radio emulator both use this queue, so a delayed neighbour message behaves the same
in both. Pure (no clock): the caller passes the current time.
"""

from __future__ import annotations

import heapq
import itertools
from dataclasses import dataclass, field
from typing import Generic, TypeVar

T = TypeVar("T")


@dataclass(order=True)
class _Entry(Generic[T]):
    delivery_t_s: float
    order: int
    receiver_id: int = field(compare=False)
    item: T = field(compare=False)


class DeliveryQueue(Generic[T]):
    """A min-heap of (delivery time, receiver, item); ``pop_due(now)`` releases what has arrived, oldest first.

    Bounded: beyond ``max_items`` the push is refused (returns False) and counted in ``overflow_count``, so a
    stalled consumer cannot grow memory without limit.
    """

    def __init__(self, max_items: int = 1_000_000) -> None:
        self._heap: list[_Entry[T]] = []
        self._counter = itertools.count()
        self.max_items = max_items
        self.overflow_count = 0

    def __len__(self) -> int:
        return len(self._heap)

    def push(self, delivery_t_s: float, receiver_id: int, item: T) -> bool:
        if len(self._heap) >= self.max_items:
            self.overflow_count += 1
            return False
        heapq.heappush(self._heap, _Entry(float(delivery_t_s), next(self._counter), int(receiver_id), item))
        return True

    def next_delivery_t_s(self) -> float | None:
        """When the earliest held item is due (None when empty): lets a loop sleep exactly that long."""
        return self._heap[0].delivery_t_s if self._heap else None

    def pop_due(self, now_s: float) -> list[tuple[float, int, T]]:
        """All items with delivery time <= now, as (delivery_t_s, receiver_id, item), in delivery order."""
        out: list[tuple[float, int, T]] = []
        heap = self._heap
        while heap and heap[0].delivery_t_s <= now_s:
            e = heapq.heappop(heap)
            out.append((e.delivery_t_s, e.receiver_id, e.item))
        return out
