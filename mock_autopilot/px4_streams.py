"""Telemetry stream rates as data: PX4's defaults and the reduced defaults the mock uses.

PX4 runs its onboard/API link (14540+i, MAVSDK) in "onboard" mode and its GCS link (14550) in "normal" mode,
with the rates below (PX4_INTERFACE.md, src/modules/mavlink/mavlink_main.cpp). The ``reduced`` profile keeps
what MAVSDK's telemetry health and an offboard controller need, at rates that let one process host many vehicles
(numbers in docs/BENCHMARKS.md). ``minimal`` sends only the 1 Hz heartbeat PX4 never switches off: for an
in-process owner that reads the vehicle's state directly (``mock_autopilot/backends/px4.py``), where building
telemetry nobody decodes is wasted CPU. SET_MESSAGE_INTERVAL overrides a rate per link at run time.
"""

from __future__ import annotations

from typing import Mapping

ONBOARD = "onboard"
GCS = "gcs"
LINKS = (ONBOARD, GCS)

STREAM_PROFILES: dict[str, dict[str, dict[str, float]]] = {
    "px4": {
        ONBOARD: {
            "HEARTBEAT": 1.0,
            "SYS_STATUS": 5.0,
            "LOCAL_POSITION_NED": 30.0,
            "GLOBAL_POSITION_INT": 50.0,
            "GPS_RAW_INT": 5.0,
            "EXTENDED_SYS_STATE": 5.0,
            "HOME_POSITION": 0.5,
            "ATTITUDE": 100.0,
            "ALTITUDE": 10.0,
            "VFR_HUD": 10.0,
            "DISTANCE_SENSOR": 10.0,
            "BATTERY_STATUS": 0.5,
            "POSITION_TARGET_LOCAL_NED": 10.0,
            "WIND_COV": 1.0,
        },
        GCS: {
            "HEARTBEAT": 1.0,
            "SYS_STATUS": 1.0,
            "LOCAL_POSITION_NED": 1.0,
            "GLOBAL_POSITION_INT": 5.0,
            "GPS_RAW_INT": 1.0,
            "EXTENDED_SYS_STATE": 1.0,
            "HOME_POSITION": 0.5,
            "ATTITUDE": 15.0,
            "ALTITUDE": 1.0,
            "VFR_HUD": 4.0,
            "DISTANCE_SENSOR": 0.5,
            "BATTERY_STATUS": 0.5,
            "POSITION_TARGET_LOCAL_NED": 1.5,
            "WIND_COV": 0.5,
        },
    },
    "reduced": {
        ONBOARD: {
            "HEARTBEAT": 1.0,
            "SYS_STATUS": 1.0,
            "LOCAL_POSITION_NED": 20.0,
            "GLOBAL_POSITION_INT": 10.0,
            "GPS_RAW_INT": 1.0,
            "EXTENDED_SYS_STATE": 2.0,
            "HOME_POSITION": 0.5,
            "ATTITUDE": 10.0,
            "ALTITUDE": 1.0,
            "VFR_HUD": 1.0,
            "DISTANCE_SENSOR": 2.0,
            "BATTERY_STATUS": 0.5,
            "POSITION_TARGET_LOCAL_NED": 2.0,
            "WIND_COV": 0.5,
        },
        GCS: {
            "HEARTBEAT": 1.0,
            "SYS_STATUS": 1.0,
            "LOCAL_POSITION_NED": 2.0,
            "GLOBAL_POSITION_INT": 2.0,
            "GPS_RAW_INT": 0.5,
            "EXTENDED_SYS_STATE": 1.0,
            "HOME_POSITION": 0.5,
            "ATTITUDE": 2.0,
            "VFR_HUD": 1.0,
            "BATTERY_STATUS": 0.5,
        },
    },
    "minimal": {
        ONBOARD: {"HEARTBEAT": 1.0},
        GCS: {"HEARTBEAT": 1.0},
    },
}

DEFAULT_PROFILE = "reduced"


def stream_periods_s(profile: str, link: str) -> dict[str, float]:
    """Message name -> period [s, simulated] for one link of a profile; raises KeyError on an unknown profile."""
    rates: Mapping[str, float] = STREAM_PROFILES[profile][link]
    return {name: 1.0 / hz for name, hz in rates.items() if hz > 0.0}
