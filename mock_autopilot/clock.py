"""The simulation clock every vehicle of a fleet shares: simulated seconds run ``speed`` times the wall clock.

Stream rates, timeouts (COM_OF_LOSS_T, auto-disarm, link loss) and physics all read this clock, so
``--speed 4`` makes a whole flight four times faster while every PX4 timing stays right in simulated time.
"""

from __future__ import annotations

import time
from typing import Callable


class SimClock:
    """Simulated time [s] since start = (wall time since start) x speed."""

    def __init__(self, speed: float = 1.0, wall_clock: Callable[[], float] = time.monotonic) -> None:
        if not speed > 0.0:
            raise ValueError(f"speed must be > 0, got {speed}")
        self.speed = float(speed)
        self._wall_clock = wall_clock
        self._wall_start_s = wall_clock()

    def now_s(self) -> float:
        """Simulated seconds since the clock started."""
        return (self._wall_clock() - self._wall_start_s) * self.speed

    def wall_delay_s(self, sim_delay_s: float) -> float:
        """How long to wait on the wall clock for ``sim_delay_s`` simulated seconds to pass."""
        return sim_delay_s / self.speed

    def unix_time_s(self) -> float:
        """Wall-clock Unix time (for MAVLink signing timestamps, which are wall time by definition)."""
        return time.time()
