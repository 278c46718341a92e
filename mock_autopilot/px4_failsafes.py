"""PX4 failsafe actions as data: what each value of COM_OBL_RC_ACT, NAV_DLL_ACT and COM_LOW_BAT_ACT does.

An action is a mode to switch to, or one of the two actions that stop the motors: TERMINATE (flight termination:
motors off, the vehicle falls, failsafe stays flagged) and DISARM (PX4's "disarm"/"lockdown").
"""

from __future__ import annotations

from typing import Literal

from comms.px4 import Px4Mode

TERMINATE: Literal["terminate"] = "terminate"
DISARM: Literal["disarm"] = "disarm"
FailsafeAction = Px4Mode | Literal["terminate", "disarm"]

OFFBOARD_LOSS_ACTIONS: dict[int, FailsafeAction] = {
    0: Px4Mode.POSCTL,
    1: Px4Mode.ALTCTL,
    2: Px4Mode.STABILIZED,
    3: Px4Mode.AUTO_RTL,
    4: Px4Mode.AUTO_LAND,
    5: Px4Mode.AUTO_LOITER,
    6: TERMINATE,
    7: DISARM,
}
"""COM_OBL_RC_ACT: 0 position, 1 altitude, 2 stabilized, 3 return, 4 land, 5 hold, 6 terminate, 7 disarm."""

DATALINK_LOSS_ACTIONS: dict[int, FailsafeAction | None] = {
    0: None,
    1: Px4Mode.AUTO_LOITER,
    2: Px4Mode.AUTO_RTL,
    3: Px4Mode.AUTO_LAND,
    4: Px4Mode.AUTO_LAND,
    5: TERMINATE,
    6: DISARM,
}
"""NAV_DLL_ACT: 0 disabled, 1 hold, 2 return, 3 land, 5 terminate, 6 lockdown (4, undefined in PX4, lands)."""

BATTERY_LEVELS = ("BAT_LOW_THR", "BAT_CRIT_THR", "BAT_EMERGEN_THR")
"""Threshold parameters of battery levels 1 (low), 2 (critical), 3 (emergency)."""


def battery_action(level: int, com_low_bat_act: int) -> Px4Mode | None:
    """COM_LOW_BAT_ACT at a battery level: 0 warn only; 1 return at critical; 2 land at critical;
    3 return at critical, land at emergency. Every action lands at emergency; low is a warning."""
    if com_low_bat_act == 0 or level < 2:
        return None
    if level >= 3 or com_low_bat_act == 2:
        return Px4Mode.AUTO_LAND
    return Px4Mode.AUTO_RTL
