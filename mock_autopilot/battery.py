"""The simulated battery: charge drawn while armed, its voltage and current, and the PX4 warning level reached.

The charge falls linearly with armed time (SIM_BAT_DRAIN seconds from full to empty, never below SIM_BAT_MIN_PCT,
as PX4's SITL battery simulator does); the levels are PX4's BAT_LOW_THR / BAT_CRIT_THR / BAT_EMERGEN_THR.
"""

from __future__ import annotations

import math
from typing import Mapping

from mock_autopilot.px4_failsafes import BATTERY_LEVELS

BATTERY_CELLS = 4
HOVER_CURRENT_A = 15.0
IDLE_CURRENT_A = 0.5
LEVEL_LABELS = {1: "low", 2: "critical", 3: "emergency"}


class Battery:
    """Remaining charge [0..1], charge drawn [mAh], and the highest warning level already reported."""

    def __init__(self) -> None:
        self.remaining = 1.0
        self.consumed_mah = 0.0
        self.level_reported = 0
        self._checked = math.nan

    def voltage_v(self) -> float:
        """Pack voltage [V]: 3.5 V per cell empty to 4.2 V full."""
        return BATTERY_CELLS * (3.5 + 0.7 * max(0.0, self.remaining))

    @staticmethod
    def current_a(armed: bool) -> float:
        """Current drawn [A]: hover current while armed, idle electronics otherwise."""
        return HOVER_CURRENT_A if armed else IDLE_CURRENT_A

    def set_remaining(self, fraction: float) -> None:
        """Drain (or refill) to ``fraction`` of capacity (fault injection)."""
        self.remaining = float(min(1.0, max(0.0, fraction)))

    def drain(self, dt_s: float, params: Mapping[str, float]) -> None:
        """Draw ``dt_s`` seconds of hover current (call only while armed)."""
        floor = params["SIM_BAT_MIN_PCT"] / 100.0
        if self.remaining > floor:
            self.remaining = max(floor, self.remaining - dt_s / params["SIM_BAT_DRAIN"])
        self.consumed_mah += HOVER_CURRENT_A * dt_s / 3.6

    def charge_state(self, params: Mapping[str, float]) -> int:
        """MAV_BATTERY_CHARGE_STATE: 1 ok, 2 low, 3 critical, 4 emergency."""
        return 1 + self._level(params)

    def new_level(self, params: Mapping[str, float]) -> int | None:
        """The warning level (1 low, 2 critical, 3 emergency) newly reached since the last call, else None."""
        if self.remaining == self._checked:
            return None
        self._checked = self.remaining
        level = self._level(params)
        if level <= self.level_reported:
            return None
        self.level_reported = level
        return level

    def _level(self, params: Mapping[str, float]) -> int:
        level = 0
        for i, name in enumerate(BATTERY_LEVELS, start=1):
            if self.remaining < params[name]:
                level = i
        return level
