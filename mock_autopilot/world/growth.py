"""How far a flood has grown at a time: the linear ramp every model shares (SPEC §3)."""

from __future__ import annotations


def growth_fraction(t_s: float, duration_s: float) -> float:
    """0 before the flood clock starts, 1 after ``duration_s``, linear in between (instant for a zero duration)."""
    if duration_s <= 0.0:
        return 1.0 if t_s >= 0.0 else 0.0
    return min(max(t_s / duration_s, 0.0), 1.0)


def ramp(start: float, end: float, t_s: float, duration_s: float) -> float:
    """The value going linearly from ``start`` (t <= 0) to ``end`` (t >= ``duration_s``)."""
    return start + (end - start) * growth_fraction(t_s, duration_s)
