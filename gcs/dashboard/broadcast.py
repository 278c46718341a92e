"""One encoded frame shared by every connected page: the frame is built and encoded once per update, however many
clients listen, and each client's stream only waits for the next version (a slow client skips frames, never
holds the others back)."""

from __future__ import annotations

import asyncio


class FrameBroadcast:
    def __init__(self) -> None:
        self._frame = b""
        self._version = 0
        self._changed = asyncio.Condition()
        self.clients = 0

    @property
    def version(self) -> int:
        return self._version

    async def publish(self, frame: bytes) -> None:
        async with self._changed:
            self._frame = frame
            self._version += 1
            self._changed.notify_all()

    async def next_frame(self, seen_version: int, timeout_s: float) -> tuple[int, bytes | None]:
        """The newest frame once it is newer than ``seen_version``; ``(seen_version, None)`` after ``timeout_s``
        without one (the caller sends a keep-alive)."""
        async with self._changed:
            try:
                await asyncio.wait_for(self._changed.wait_for(lambda: self._version != seen_version), timeout_s)
            except asyncio.TimeoutError:
                return seen_version, None
            return self._version, self._frame
