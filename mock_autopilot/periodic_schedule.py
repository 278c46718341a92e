"""Things done periodically in simulated time: a fixed grid of slots ``k * period`` that skips the slots it missed.

A camera takes frames at its own rate (``[camera] rate_hz``), slower than the control loop; the fleet publishes its
truth at the control rate; a ground station sends a HEARTBEAT every second. Each falls on the grid of its period in
mission time, in both engines. One that falls behind skips the slots it missed instead of bursting to catch up, as a
real camera drops frames, and stays on the grid.
"""

from __future__ import annotations

import math

TIME_EPSILON_S = 1e-9
"""Times this close count as equal (sums of periods carry rounding)."""


def slot_reached(due_s: float, now_s: float) -> bool:
    """Is the slot at ``due_s`` reached at ``now_s``?"""
    return now_s + TIME_EPSILON_S >= due_s


def next_slot_s(due_s: float, period_s: float, now_s: float) -> float:
    """The grid slot after the one at ``due_s`` that is still ahead of ``now_s`` (slots missed are skipped)."""
    missed = max(0, math.floor((now_s + TIME_EPSILON_S - due_s) / period_s))
    return due_s + period_s * (missed + 1)
