"""A downward rangefinder as PX4 reports it: DISTANCE_SENSOR (MAVLink #132), pure.

PX4 streams DISTANCE_SENSOR for a downward-facing sensor (orientation ``MAV_SENSOR_ROTATION_PITCH_270``) at 10 Hz
on an onboard link and 0.5 Hz on a normal (GCS) link, distances in centimetres, with the sensor's valid range;
a reading outside the range is reported clamped to it (a real sensor reports its limit or nothing). Over relief the
drone holds its altitude above home, and this is how a companion computer learns how far the ground really is.
"""

from __future__ import annotations

import math

from pymavlink.dialects.v20 import common as mavlink

MIN_DISTANCE_M = 0.1
"""Closest distance the simulated sensor measures [m] (a lidar such as the LightWare SF11 or TFmini starts at ~0.1 m)."""
MAX_DISTANCE_M = 40.0
"""Farthest distance it measures [m]."""
SENSOR_ID = 0


def distance_sensor_message(time_boot_ms: int, height_above_ground_m: float) -> mavlink.MAVLink_message:
    """DISTANCE_SENSOR for a downward laser rangefinder reading ``height_above_ground_m``; NaN reads as its maximum."""
    distance_m = height_above_ground_m if math.isfinite(height_above_ground_m) else MAX_DISTANCE_M
    distance_m = min(max(distance_m, MIN_DISTANCE_M), MAX_DISTANCE_M)
    return mavlink.MAVLink_distance_sensor_message(
        time_boot_ms, int(round(MIN_DISTANCE_M * 100)), int(round(MAX_DISTANCE_M * 100)),
        int(round(distance_m * 100)), mavlink.MAV_DISTANCE_SENSOR_LASER, SENSOR_ID,
        mavlink.MAV_SENSOR_ROTATION_PITCH_270, 255,
    )
