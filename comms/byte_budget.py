"""A bandwidth limit per sender in bytes per mission second: a token bucket, advanced message by message (pure).

A real swarm radio carries a limited number of bytes per second per node (a shared channel, a duty cycle): a
drone that sends more has the excess dropped at its own radio, never reaching anyone. The bucket fills at
``rate_bytes_per_s`` up to ``depth_bytes`` (one second's worth by default) and a message leaves only when the bucket
holds its whole size; otherwise it is dropped and counted. The state is one level and one time per sender, driven
by the sender's own mission time stamps and message sizes, which both engines see identically (the same encoded
message, the same ``t_s``), so both drop the same messages.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class BucketLevel:
    """One sender's bucket: bytes available after its last message, and that message's time [s]."""

    level_bytes: float
    t_s: float


def admit(level: BucketLevel | None, size_bytes: int, t_s: float, rate_bytes_per_s: float,
          depth_bytes: float) -> tuple[bool, BucketLevel]:
    """Whether a message of ``size_bytes`` sent at ``t_s`` leaves, and the bucket after it (a full bucket first).

    A time stamp older than the bucket's (reordered input, a restarted sender) refills nothing and is judged on
    the level at hand.
    """
    if level is None:
        available = depth_bytes
    else:
        available = min(depth_bytes, level.level_bytes + rate_bytes_per_s * max(0.0, t_s - level.t_s))
    latest_t_s = t_s if level is None else max(t_s, level.t_s)
    if size_bytes <= available:
        return True, BucketLevel(available - size_bytes, latest_t_s)
    return False, BucketLevel(available, latest_t_s)


class SenderBudgets:
    """Every sender's bucket, by vehicle id: the thin stateful holder each engine keeps for :func:`admit`."""

    def __init__(self, rate_bytes_per_s: float, depth_s: float = 1.0) -> None:
        self.rate_bytes_per_s = rate_bytes_per_s
        self.depth_bytes = rate_bytes_per_s * depth_s
        self.dropped = 0
        self.dropped_bytes = 0
        self._levels: dict[int, BucketLevel] = {}

    @property
    def limited(self) -> bool:
        return self.rate_bytes_per_s > 0.0

    def admit(self, sender_id: int, size_bytes: int, t_s: float) -> bool:
        """Whether this message leaves its sender (always, without a limit); drops are counted."""
        if not self.limited:
            return True
        ok, self._levels[sender_id] = admit(self._levels.get(sender_id), size_bytes, t_s, self.rate_bytes_per_s,
                                            self.depth_bytes)
        if not ok:
            self.dropped += 1
            self.dropped_bytes += size_bytes
        return ok
