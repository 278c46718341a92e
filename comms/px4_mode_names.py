"""PX4's flight modes by name only: the name QGroundControl shows (PX4 commander's) and the name MAVSDK's
``FlightMode`` gives each one.

An onboard agent that flies through MAVSDK compares the mode name in its telemetry with OFFBOARD and never sees a
MAVLink number, so it imports this module and not :mod:`comms.px4`, whose numbers come from pymavlink's MAVLink
dialect (~6 MiB of private memory and tens of milliseconds of start-up in every agent process otherwise). Nothing
here is a MAVLink number and nothing here imports pymavlink; :mod:`comms.px4` builds its mode table on these names
and re-exports them, so it stays the one place where a mode meets its numbers.
"""

from __future__ import annotations

from enum import Enum


class Px4Mode(Enum):
    """The PX4 navigation modes a multicopter flies without RC; the value is the name QGroundControl shows."""

    MANUAL = "MANUAL"
    ALTCTL = "ALTCTL"
    POSCTL = "POSCTL"
    OFFBOARD = "OFFBOARD"
    STABILIZED = "STABILIZED"
    AUTO_READY = "AUTO.READY"
    AUTO_TAKEOFF = "AUTO.TAKEOFF"
    AUTO_LOITER = "AUTO.LOITER"
    AUTO_MISSION = "AUTO.MISSION"
    AUTO_RTL = "AUTO.RTL"
    AUTO_LAND = "AUTO.LAND"


MAVSDK_NAMES: dict[Px4Mode, str] = {
    Px4Mode.MANUAL: "MANUAL",
    Px4Mode.ALTCTL: "ALTCTL",
    Px4Mode.POSCTL: "POSCTL",
    Px4Mode.AUTO_READY: "READY",
    Px4Mode.AUTO_TAKEOFF: "TAKEOFF",
    Px4Mode.AUTO_LOITER: "HOLD",
    Px4Mode.AUTO_MISSION: "MISSION",
    Px4Mode.AUTO_RTL: "RETURN_TO_LAUNCH",
    Px4Mode.AUTO_LAND: "LAND",
    Px4Mode.OFFBOARD: "OFFBOARD",
    Px4Mode.STABILIZED: "STABILIZED",
}
"""Each mode as MAVSDK's ``FlightMode`` names it, which is what an onboard agent's telemetry carries."""

MAVSDK_MODE_NAMES: dict[str, str] = {mode.value: name for mode, name in MAVSDK_NAMES.items()}
"""PX4's own mode name (QGroundControl's, ``Px4Mode.value``) -> the name MAVSDK's ``FlightMode`` gives it. The two
agree on OFFBOARD, the mode the flight phase tests."""

MAVSDK_OFFBOARD: str = MAVSDK_NAMES[Px4Mode.OFFBOARD]
"""OFFBOARD as MAVSDK's telemetry names it (what an onboard agent compares its flight mode with)."""
