"""The one place where frames are converted.

Frames used in FloodWatch:

* **mission ENU** — east, north, up in metres around a geodetic home (the launch site). The flood world,
  the control laws and the metrics all live here.
* **vehicle local NED** — north, east, down in metres from the vehicle's own boot position (its pad), as PX4
  reports it in LOCAL_POSITION_NED and accepts it in SET_POSITION_TARGET_LOCAL_NED.
* **WGS84 geodetic** — latitude and longitude in degrees, altitude AMSL in metres (GLOBAL_POSITION_INT, GeoJSON).

Geodetic <-> ENU uses the azimuthal equidistant projection on a sphere, the same projection PX4 uses for its
local/global reference, so a position computed here agrees with a real PX4's to the centimetre over a flood's size.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mission_plan.home import GeodeticHome

EARTH_RADIUS_M = 6_371_000.0


def enu_to_ned(vector_enu: ArrayLike) -> NDArray[np.float64]:
    """Swap an ENU vector (or an (..., 3) array of them) into NED; works for positions and velocities."""
    v = np.asarray(vector_enu, dtype=float)
    return np.stack([v[..., 1], v[..., 0], -v[..., 2]], axis=-1)


def ned_to_enu(vector_ned: ArrayLike) -> NDArray[np.float64]:
    """Swap a NED vector (or an (..., 3) array of them) into ENU; the map is its own inverse."""
    v = np.asarray(vector_ned, dtype=float)
    return np.stack([v[..., 1], v[..., 0], -v[..., 2]], axis=-1)


def swap_ned_enu(x: float, y: float, z: float) -> tuple[float, float, float]:
    """One vector swapped between NED and ENU (either way: the map is its own inverse) as plain floats: the per-drone
    hot path of every control step, where numpy on a 3-vector costs more than the arithmetic."""
    return float(y), float(x), -float(z)


def local_ned_to_mission_enu(position_ned_m: ArrayLike, pad_enu_m: ArrayLike) -> NDArray[np.float64]:
    """A vehicle's local NED position (origin at its pad) expressed in the mission ENU frame."""
    return ned_to_enu(position_ned_m) + np.asarray(pad_enu_m, dtype=float)


def mission_enu_to_local_ned(position_enu_m: ArrayLike, pad_enu_m: ArrayLike) -> NDArray[np.float64]:
    """A mission ENU position expressed in the local NED frame of the vehicle whose pad is at ``pad_enu_m``."""
    return enu_to_ned(np.asarray(position_enu_m, dtype=float) - np.asarray(pad_enu_m, dtype=float))


def enu_to_geodetic(position_enu_m: ArrayLike, home: GeodeticHome) -> NDArray[np.float64]:
    """Mission ENU [m] -> (lat_deg, lon_deg, alt_m AMSL); vectorised over (..., 3) or (..., 2) arrays.

    With (..., 2) input the altitude column is the home altitude.
    """
    p = np.asarray(position_enu_m, dtype=float)
    east = p[..., 0] / EARTH_RADIUS_M
    north = p[..., 1] / EARTH_RADIUS_M
    up = p[..., 2] if p.shape[-1] > 2 else np.zeros_like(east)
    lat0 = math.radians(home.lat_deg)
    lon0 = math.radians(home.lon_deg)
    c = np.hypot(north, east)
    sin_c = np.sin(c)
    cos_c = np.cos(c)
    safe_c = np.where(c > 0.0, c, 1.0)
    lat = np.where(
        c > 0.0,
        np.arcsin(np.clip(cos_c * math.sin(lat0) + north * sin_c * math.cos(lat0) / safe_c, -1.0, 1.0)),
        lat0,
    )
    lon = np.where(
        c > 0.0,
        lon0 + np.arctan2(east * sin_c, c * math.cos(lat0) * cos_c - north * math.sin(lat0) * sin_c),
        lon0,
    )
    return np.stack([np.degrees(lat), np.degrees(lon), home.alt_m + up], axis=-1)


def geodetic_to_enu(lat_deg: ArrayLike, lon_deg: ArrayLike, alt_m: ArrayLike, home: GeodeticHome) -> NDArray[np.float64]:
    """(lat_deg, lon_deg, alt_m AMSL) -> mission ENU [m]; the inverse of :func:`enu_to_geodetic`."""
    lat = np.radians(np.asarray(lat_deg, dtype=float))
    lon = np.radians(np.asarray(lon_deg, dtype=float))
    lat0 = math.radians(home.lat_deg)
    lon0 = math.radians(home.lon_deg)
    cos_dlon = np.cos(lon - lon0)
    arg = np.clip(math.sin(lat0) * np.sin(lat) + math.cos(lat0) * np.cos(lat) * cos_dlon, -1.0, 1.0)
    c = np.arccos(arg)
    k = np.where(np.abs(c) > 1e-12, c / np.where(np.abs(c) > 1e-12, np.sin(c), 1.0), 1.0)
    north = k * (math.cos(lat0) * np.sin(lat) - math.sin(lat0) * np.cos(lat) * cos_dlon) * EARTH_RADIUS_M
    east = k * np.cos(lat) * np.sin(lon - lon0) * EARTH_RADIUS_M
    up = np.asarray(alt_m, dtype=float) - home.alt_m
    return np.stack([east, north, up * np.ones_like(east)], axis=-1)


def yaw_ned_to_enu_rad(yaw_ned_rad: float) -> float:
    """PX4 yaw (clockwise from north) -> ENU heading (counter-clockwise from east), both in radians."""
    return math.atan2(math.cos(yaw_ned_rad), math.sin(yaw_ned_rad))


def yaw_enu_to_ned_rad(heading_enu_rad: float) -> float:
    """ENU heading (counter-clockwise from east) -> PX4 yaw (clockwise from north), both in radians."""
    return math.atan2(math.cos(heading_enu_rad), math.sin(heading_enu_rad))


def body_frd_to_ned(vector_frd: ArrayLike, yaw_ned_rad: float) -> NDArray[np.float64]:
    """Rotate a body-frame (forward, right, down) vector into NED by the vehicle's yaw (level flight).

    Used for MAVLink's MAV_FRAME_BODY_NED setpoints, which PX4 rotates by the current heading only.
    """
    v = np.asarray(vector_frd, dtype=float)
    c, s = math.cos(yaw_ned_rad), math.sin(yaw_ned_rad)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1], v[..., 2]], axis=-1)


def body_fr_to_en(vector_fr_m: ArrayLike, yaw_ned_rad: float) -> NDArray[np.float64]:
    """Rotate horizontal body-frame (forward, right) vectors (..., 2) into mission (east, north) by the yaw (level)."""
    v = np.asarray(vector_fr_m, dtype=float)
    c, s = math.cos(yaw_ned_rad), math.sin(yaw_ned_rad)
    return np.stack([s * v[..., 0] + c * v[..., 1], c * v[..., 0] - s * v[..., 1]], axis=-1)


def en_to_body_fr(vector_en_m: ArrayLike, yaw_ned_rad: float) -> NDArray[np.float64]:
    """Rotate mission (east, north) vectors (..., 2) into the horizontal body frame (forward, right) by the yaw (the
    same matrix as :func:`body_fr_to_en`: swapping the axes' order and handedness makes the map its own inverse)."""
    return body_fr_to_en(vector_en_m, yaw_ned_rad)


def body_to_ned_matrix(roll_rad: float, pitch_rad: float, yaw_ned_rad: float) -> NDArray[np.float64]:
    """3x3 rotation taking a body (forward, right, down) vector into NED: PX4's Euler angles, yaw-pitch-roll (Z-Y-X)
    order, as ATTITUDE reports them."""
    cr, sr = math.cos(roll_rad), math.sin(roll_rad)
    cp, sp = math.cos(pitch_rad), math.sin(pitch_rad)
    cy, sy = math.cos(yaw_ned_rad), math.sin(yaw_ned_rad)
    return np.array([
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ])
