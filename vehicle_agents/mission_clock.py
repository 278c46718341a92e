"""How an agent knows the mission time when the simulation runs faster than the wall clock.

Everything on the mission's Zenoh keys is stamped with mission time: the simulator's clock, which runs ``speed``
times faster than the wall clock (``--speed``). An agent cannot read that clock directly (a real PX4 has no such
thing), so it keeps its own: wall time since start times the speed factor, re-anchored to the newest mission time
stamp it receives from the ground station's commands or its camera frames (both carry the simulator's time). With a
real vehicle the speed is 1 and no stamps are needed. The same speed factor sets the wall-clock period of the
control loop: 20 Hz in mission time is ``20 * speed`` Hz on the wall clock.

Re-anchoring only ever moves the clock forward by the observed lag and slews backwards slowly, so the control law
never sees time run backwards.
"""

from __future__ import annotations

import time
from collections.abc import Callable


class MissionClock:
    """Mission time [s] estimated from the wall clock, the speed factor and received time stamps."""

    def __init__(self, speed: float, monotonic: Callable[[], float] = time.monotonic) -> None:
        if not speed > 0.0:
            raise ValueError(f"speed: must be > 0, got {speed}")
        self.speed = speed
        self._monotonic = monotonic
        self._anchor_wall_s = monotonic()
        self._anchor_mission_s = 0.0
        self._last_now_s = 0.0
        self.synced = False

    def now_s(self) -> float:
        t = self._anchor_mission_s + (self._monotonic() - self._anchor_wall_s) * self.speed
        self._last_now_s = max(self._last_now_s, t)
        return self._last_now_s

    def observe(self, stamp_mission_s: float) -> None:
        """A message stamped ``stamp_mission_s`` just arrived: the clock is at least that late.

        The first stamp sets the clock; later ones pull it forward at once when it lags, and back by at most 10 %
        of the difference when it runs ahead (delivery delays only ever make stamps look old).
        """
        now_wall_s = self._monotonic()
        estimate_s = self._anchor_mission_s + (now_wall_s - self._anchor_wall_s) * self.speed
        if not self.synced or stamp_mission_s > estimate_s:
            target_s = stamp_mission_s
        else:
            target_s = estimate_s + 0.1 * (stamp_mission_s - estimate_s)
        self._anchor_wall_s, self._anchor_mission_s = now_wall_s, target_s
        self.synced = True

    def wall_period_s(self, mission_period_s: float) -> float:
        """Wall-clock seconds of a period given in mission seconds."""
        return mission_period_s / self.speed
