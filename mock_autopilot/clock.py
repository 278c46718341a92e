"""The simulation clock every vehicle of a fleet shares: simulated seconds run ``speed`` times the wall clock.

Stream rates, timeouts (COM_OF_LOSS_T, auto-disarm) and physics all read this clock, so ``--speed 4`` makes a whole
flight four times faster while every PX4 timing stays right in simulated time.

A paced clock (``--clock paced``) also has a gate: simulated time never passes it. The pacer
(:mod:`mock_autopilot.pacing`) moves the gate one control tick at a time once every participant has acted on the
previous one: the lockstep of PX4 SITL with Gazebo, so a slow host gives a slower run, never a different one.
``speed`` stays the pace the clock keeps when nobody holds it back: a clock that stood at its gate catches up at
once when the gate moves, up to the gate, so time spent waiting for participants is not lost twice.
"""

from __future__ import annotations

import math
import threading
import time
from typing import Callable


class SimClock:
    """Simulated time [s] since start = (wall time since start) x speed, never past the gate (default: none)."""

    def __init__(self, speed: float = 1.0, wall_clock: Callable[[], float] = time.monotonic,
                 gate_s: float = math.inf) -> None:
        if not speed > 0.0:
            raise ValueError(f"speed must be > 0, got {speed}")
        self.speed = float(speed)
        self._wall_clock = wall_clock
        self._lock = threading.Lock()
        self._wall_start_s = wall_clock()
        self._gate_s = gate_s

    @property
    def gate_s(self) -> float:
        return self._gate_s

    def _free_s(self, wall_s: float) -> float:
        return (wall_s - self._wall_start_s) * self.speed

    def now_s(self) -> float:
        """Simulated seconds since the clock started."""
        with self._lock:
            return min(self._free_s(self._wall_clock()), self._gate_s)

    def held(self) -> bool:
        """Is the clock standing at its gate?"""
        with self._lock:
            return self._free_s(self._wall_clock()) >= self._gate_s

    def set_gate(self, gate_s: float) -> None:
        """Let simulated time run up to ``gate_s`` (never backwards: a lower gate than now holds it where it is)."""
        with self._lock:
            self._gate_s = max(gate_s, min(self._free_s(self._wall_clock()), self._gate_s))

    def wall_delay_s(self, sim_delay_s: float) -> float:
        """How long to wait on the wall clock for ``sim_delay_s`` simulated seconds to pass (if not held)."""
        return sim_delay_s / self.speed

    def unix_time_s(self) -> float:
        """Wall-clock Unix time (for MAVLink signing timestamps, which are wall time by definition)."""
        return time.time()
