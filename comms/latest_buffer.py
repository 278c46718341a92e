"""A bounded latest-value buffer: the hand-over point between Zenoh's threads and our consumers.

Zenoh runs subscriber callbacks on its own threads; a callback that blocks stalls the session, and one that calls
back into Zenoh can deadlock it. So callbacks only store the sample here (a dict assignment under a lock held for
a few microseconds) and return. Consumers drain the buffer from a thread (``wait``) or from asyncio
(``wait_async``). Only the newest value per key matters for states, truth and camera frames: an older one is
overwritten and counted as superseded, so a slow consumer sees fresh data instead of a growing backlog, and memory
is bounded by ``max_keys``.
"""

from __future__ import annotations

import asyncio
import threading
import time
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Literal

SampleKind = Literal["put", "delete"]


@dataclass(frozen=True)
class Received:
    """One sample as handed over: the key it came on, its raw payload, PUT/DELETE, when it arrived
    (``time.monotonic()`` of this host, comparable across processes on one machine), and the Zenoh id of the session
    that published it when the sample says so (empty otherwise)."""

    key: str
    payload: bytes
    kind: SampleKind
    rx_monotonic_s: float
    source: str = ""


class LatestValueBuffer:
    """Newest ``Received`` per key since the last ``drain``; thread-safe; never blocks the producer.

    Counters: ``received`` (all puts), ``superseded`` (overwritten before being drained), ``rejected`` (new keys
    refused because ``max_keys`` distinct keys are pending).
    """

    def __init__(self, max_keys: int = 4096) -> None:
        self.max_keys = max_keys
        self._pending: dict[str, Received] = {}
        self._cond = threading.Condition(threading.Lock())
        self._async_waiters: list[tuple[asyncio.AbstractEventLoop, asyncio.Future[None]]] = []
        self.received = 0
        self.superseded = 0
        self.rejected = 0

    def __len__(self) -> int:
        with self._cond:
            return len(self._pending)

    def put(self, key: str, payload: bytes, kind: SampleKind = "put", rx_monotonic_s: float | None = None,
            source: str = "") -> None:
        """Store one sample (called from Zenoh threads: O(1), no I/O, no Zenoh calls)."""
        self.put_many([(key, payload)], kind, rx_monotonic_s, source)

    def put_many(self, items: Iterable[tuple[str, bytes]], kind: SampleKind = "put", rx_monotonic_s: float | None = None,
                 source: str = "") -> None:
        """Store several (key, payload) samples at once (one lock, one wake-up): used for radio bundles."""
        t = time.monotonic() if rx_monotonic_s is None else rx_monotonic_s
        waiters: list[tuple[asyncio.AbstractEventLoop, asyncio.Future[None]]] = []
        with self._cond:
            pending = self._pending
            for key, payload in items:
                self.received += 1
                if key in pending:
                    self.superseded += 1
                elif len(pending) >= self.max_keys:
                    self.rejected += 1
                    continue
                pending[key] = Received(key, payload, kind, t, source)
            self._cond.notify_all()
            if self._async_waiters:
                waiters, self._async_waiters = self._async_waiters, []
        for loop, waiter in waiters:
            try:
                loop.call_soon_threadsafe(_wake, waiter)
            except RuntimeError:  # the loop was closed meanwhile: nobody is waiting any more
                pass

    def drain(self) -> list[Received]:
        """Take everything pending (newest per key), in arrival order of the keys' first pending sample."""
        with self._cond:
            items = list(self._pending.values())
            self._pending.clear()
        return items

    def wait(self, timeout_s: float | None = None) -> bool:
        """Block the calling (non-Zenoh) thread until something is pending or the timeout passes; True if pending."""
        with self._cond:
            if self._pending:
                return True
            self._cond.wait(timeout_s)
            return bool(self._pending)

    async def wait_async(self, timeout_s: float | None = None) -> bool:
        """The asyncio twin of ``wait``: awaits without blocking the event loop; True if something is pending.

        One future and one timer per wait (an agent waits once per control tick): ``asyncio.wait_for`` on an
        ``asyncio.Event`` would add a task and its steps every time.
        """
        loop = asyncio.get_running_loop()
        waiter: asyncio.Future[None] = loop.create_future()
        with self._cond:
            if self._pending:
                return True
            self._async_waiters.append((loop, waiter))
        timer = None if timeout_s is None else loop.call_later(timeout_s, _wake, waiter)
        try:
            await waiter
        finally:
            if timer is not None:
                timer.cancel()
            with self._cond:
                if (loop, waiter) in self._async_waiters:
                    self._async_waiters.remove((loop, waiter))
        with self._cond:
            return bool(self._pending)

    def wake(self) -> None:
        """Wake every waiter without data (used on shutdown so consumer loops notice a stop flag)."""
        with self._cond:
            self._cond.notify_all()
            waiters, self._async_waiters = self._async_waiters, []
        for loop, waiter in waiters:
            try:
                loop.call_soon_threadsafe(_wake, waiter)
            except RuntimeError:
                pass


def _wake(waiter: asyncio.Future[None]) -> None:
    """Resolve a waiter once (a put and its timeout may both get there)."""
    if not waiter.done():
        waiter.set_result(None)
