"""What every Zenoh message schema checks on construction: finite numbers, and the error a broken one raises."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

Point2 = tuple[float, float]
Point3 = tuple[float, float, float]


class InvalidMessage(ValueError):
    """A message that breaks a schema check (NaN position, negative id, ...). Raised when such a message is
    constructed (a sender bug surfaces at the sender); on receipt ``decode`` turns it into None + ``invalid``."""


def finite(*values: float) -> bool:
    return all(math.isfinite(v) for v in values)


def finite_points(points: Iterable[Sequence[float]]) -> bool:
    """All coordinates finite (one C-level sum: NaN and inf propagate through it)."""
    return math.isfinite(sum(map(sum, points)))
