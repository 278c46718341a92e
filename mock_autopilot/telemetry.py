"""Outgoing telemetry built from a vehicle's state: one pure builder per streamed message.

Each builder takes the vehicle (read only) and the simulated time and returns a pymavlink message, or None when
PX4 would not send it (no GLOBAL_POSITION_INT without a global position, no HOME_POSITION before home is set).
Contents follow PX4_INTERFACE.md; the SYS_STATUS bits are the ones MAVSDK's telemetry health reads:
GPS present+healthy -> is_global_position_ok; VISION_POSITION (our odometry, every vehicle has it) ->
is_local_position_ok; PREARM_CHECK healthy -> is_armable.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable

import numpy as np
from pymavlink.dialects.v20 import common as mavlink

from comms.frames import enu_to_geodetic, local_ned_to_mission_enu
from mock_autopilot.px4_modes import base_mode, custom_mode
from mock_autopilot.rangefinder import distance_sensor_message

if TYPE_CHECKING:
    from mock_autopilot.vehicle import Vehicle

MAV_TYPE_QUADROTOR = 2
MAV_AUTOPILOT_PX4 = 12
MAV_STATE_STANDBY = 3
MAV_STATE_ACTIVE = 4
MAV_STATE_CRITICAL = 5
PX4_FLIGHT_SW_VERSION = (1 << 24) | (14 << 16) | (0 << 8) | 255  # 1.14.0 official

_BASE_SENSORS = (
    mavlink.MAV_SYS_STATUS_SENSOR_3D_GYRO
    | mavlink.MAV_SYS_STATUS_SENSOR_3D_ACCEL
    | mavlink.MAV_SYS_STATUS_SENSOR_3D_MAG
    | mavlink.MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE
    | mavlink.MAV_SYS_STATUS_SENSOR_VISION_POSITION
    | mavlink.MAV_SYS_STATUS_SENSOR_ANGULAR_RATE_CONTROL
    | mavlink.MAV_SYS_STATUS_SENSOR_ATTITUDE_STABILIZATION
    | mavlink.MAV_SYS_STATUS_SENSOR_YAW_POSITION
    | mavlink.MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL
    | mavlink.MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL
    | mavlink.MAV_SYS_STATUS_SENSOR_MOTOR_OUTPUTS
    | mavlink.MAV_SYS_STATUS_AHRS
    | mavlink.MAV_SYS_STATUS_SENSOR_BATTERY
    | mavlink.MAV_SYS_STATUS_PREARM_CHECK
)

AUTOPILOT_CAPABILITIES = (
    mavlink.MAV_PROTOCOL_CAPABILITY_MISSION_INT
    | mavlink.MAV_PROTOCOL_CAPABILITY_COMMAND_INT
    | mavlink.MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_BYTEWISE
    | mavlink.MAV_PROTOCOL_CAPABILITY_SET_POSITION_TARGET_LOCAL_NED
    | mavlink.MAV_PROTOCOL_CAPABILITY_FLIGHT_TERMINATION
    | mavlink.MAV_PROTOCOL_CAPABILITY_MAVLINK2
)


def time_boot_ms(v: Vehicle, now_s: float) -> int:
    """Milliseconds since the vehicle booted, wrapped to uint32."""
    return int(max(0.0, now_s - v.boot_time_s) * 1000.0) & 0xFFFFFFFF


def geodetic_of(v: Vehicle, position_ned_m: np.ndarray) -> tuple[float, float, float]:
    """(lat_deg, lon_deg, alt_m AMSL) of a local NED position of this vehicle (home + pad + local).

    The last conversion is remembered: GLOBAL_POSITION_INT and GPS_RAW_INT of one tick share it.
    """
    key = (float(position_ned_m[0]), float(position_ned_m[1]), float(position_ned_m[2]))
    cached = v.geodetic_cache
    if cached is not None and cached[0] == key:
        return cached[1]
    enu = local_ned_to_mission_enu(position_ned_m, v.config.pad_enu_m)
    lat, lon, alt = enu_to_geodetic(enu, v.config.home)
    result = (float(lat), float(lon), float(alt))
    v.geodetic_cache = (key, result)
    return result


def _i16(value: float) -> int:
    return int(max(-32768, min(32767, round(value))))


def heartbeat(v: Vehicle, now_s: float) -> mavlink.MAVLink_message:
    if v.failsafe:
        status = MAV_STATE_CRITICAL
    else:
        status = MAV_STATE_ACTIVE if v.armed else MAV_STATE_STANDBY
    return mavlink.MAVLink_heartbeat_message(
        MAV_TYPE_QUADROTOR, MAV_AUTOPILOT_PX4, base_mode(v.mode, v.armed), custom_mode(v.mode), status, 3
    )


def sys_status(v: Vehicle, now_s: float) -> mavlink.MAVLink_message:
    present = _BASE_SENSORS | (mavlink.MAV_SYS_STATUS_SENSOR_GPS if v.config.has_gps else 0)
    health = present
    if not v.global_position_valid:
        health &= ~mavlink.MAV_SYS_STATUS_SENSOR_GPS
    if v.arming_denial(now_s) is not None:
        health &= ~mavlink.MAV_SYS_STATUS_PREARM_CHECK
    if v.battery_remaining < v.params["BAT_CRIT_THR"]:
        health &= ~mavlink.MAV_SYS_STATUS_SENSOR_BATTERY
    return mavlink.MAVLink_sys_status_message(
        present, present, health, 200, int(v.battery_voltage_v * 1000), int(v.battery_current_a * 100),
        int(round(v.battery_remaining * 100)), 0, 0, 0, 0, 0, 0,
    )


def local_position_ned(v: Vehicle, now_s: float) -> mavlink.MAVLink_message:
    p, vel = v.position_ned_m, v.velocity_ned_mps
    return mavlink.MAVLink_local_position_ned_message(
        time_boot_ms(v, now_s), float(p[0]), float(p[1]), float(p[2]), float(vel[0]), float(vel[1]), float(vel[2])
    )


def global_position_int(v: Vehicle, now_s: float) -> mavlink.MAVLink_message | None:
    if not v.global_position_valid:
        return None
    lat, lon, alt = geodetic_of(v, v.position_ned_m)
    vel = v.velocity_ned_mps
    heading_cdeg = int(round(math.degrees(v.yaw_rad) * 100)) % 36000
    relative_m = -float(v.position_ned_m[2]) + float(v.home_ned_m[2])
    return mavlink.MAVLink_global_position_int_message(
        time_boot_ms(v, now_s), int(round(lat * 1e7)), int(round(lon * 1e7)), int(round(alt * 1000)),
        int(round(relative_m * 1000)), _i16(vel[0] * 100), _i16(vel[1] * 100), _i16(vel[2] * 100), heading_cdeg,
    )


def gps_raw_int(v: Vehicle, now_s: float) -> mavlink.MAVLink_message:
    usec = int(now_s * 1e6)
    if not v.global_position_valid:
        fix = 1 if v.config.has_gps else 0
        return mavlink.MAVLink_gps_raw_int_message(usec, fix, 0, 0, 0, 65535, 65535, 65535, 65535, 0)
    lat, lon, alt = geodetic_of(v, v.position_ned_m)
    vel = v.velocity_ned_mps
    ground_speed = math.hypot(vel[0], vel[1])
    cog = int(round(math.degrees(math.atan2(vel[1], vel[0])) * 100)) % 36000
    return mavlink.MAVLink_gps_raw_int_message(
        usec, 3, int(round(lat * 1e7)), int(round(lon * 1e7)), int(round(alt * 1000)), 80, 120,
        int(round(ground_speed * 100)), cog, 12,
    )


def extended_sys_state(v: Vehicle, now_s: float) -> mavlink.MAVLink_message:
    return mavlink.MAVLink_extended_sys_state_message(0, int(v.landed_state))


def home_position(v: Vehicle, now_s: float) -> mavlink.MAVLink_message | None:
    if not v.home_valid:
        return None
    lat, lon, alt = geodetic_of(v, v.home_ned_m)
    h = v.home_ned_m
    return mavlink.MAVLink_home_position_message(
        int(round(lat * 1e7)), int(round(lon * 1e7)), int(round(alt * 1000)), float(h[0]), float(h[1]), float(h[2]),
        [1.0, 0.0, 0.0, 0.0], 0.0, 0.0, 0.0, int(now_s * 1e6),
    )


def attitude(v: Vehicle, now_s: float) -> mavlink.MAVLink_message:
    roll, pitch = v.tilt_rad()
    return mavlink.MAVLink_attitude_message(
        time_boot_ms(v, now_s), roll, pitch, float(_wrap_pi(v.yaw_rad)), 0.0, 0.0, float(v.yaw_rate_rad_s)
    )


def altitude(v: Vehicle, now_s: float) -> mavlink.MAVLink_message:
    local_up = -float(v.position_ned_m[2])
    amsl = v.config.home.alt_m + float(v.config.pad_enu_m[2]) + local_up
    home_up = -float(v.home_ned_m[2])
    return mavlink.MAVLink_altitude_message(
        int(now_s * 1e6), amsl, amsl, local_up, local_up - home_up, float("nan"), local_up
    )


def vfr_hud(v: Vehicle, now_s: float) -> mavlink.MAVLink_message:
    vel = v.velocity_ned_mps
    speed = float(math.hypot(vel[0], vel[1]))
    amsl = v.config.home.alt_m + float(v.config.pad_enu_m[2]) - float(v.position_ned_m[2])
    heading = int(round(math.degrees(v.yaw_rad))) % 360
    throttle = 50 if v.armed and v.landed_state != 1 else 0
    return mavlink.MAVLink_vfr_hud_message(speed, speed, heading, throttle, amsl, -float(vel[2]))


def distance_sensor(v: Vehicle, now_s: float) -> mavlink.MAVLink_message:
    """The downward rangefinder: mission up (pad height + local up) minus the ground below (``rangefinder.py``)."""
    up = float(v.config.pad_enu_m[2]) - float(v.position_ned_m[2])
    return distance_sensor_message(time_boot_ms(v, now_s), up - v.ground_below_enu_m)


def battery_status(v: Vehicle, now_s: float) -> mavlink.MAVLink_message:
    voltages = [int(v.battery_voltage_v * 1000)] + [65535] * 9
    remaining = v.battery_remaining
    if remaining < v.params["BAT_EMERGEN_THR"]:
        charge_state = 4
    elif remaining < v.params["BAT_CRIT_THR"]:
        charge_state = 3
    elif remaining < v.params["BAT_LOW_THR"]:
        charge_state = 2
    else:
        charge_state = 1
    return mavlink.MAVLink_battery_status_message(
        0, 0, 1, 32767, voltages, int(v.battery_current_a * 100), int(v.battery_consumed_mah), -1,
        int(round(remaining * 100)), 0, charge_state, [0, 0, 0, 0], 0, 0,
    )


def position_target_local_ned(v: Vehicle, now_s: float) -> mavlink.MAVLink_message | None:
    sp = v.offboard_setpoint
    if sp is None:
        return None
    return mavlink.MAVLink_position_target_local_ned_message(
        time_boot_ms(v, now_s), 1, sp.type_mask, *sp.position_ned_m, *sp.velocity_ned_mps,
        *sp.acceleration_ned_mps2, sp.yaw_rad, sp.yaw_rate_rad_s,
    )


def autopilot_version(v: Vehicle, now_s: float) -> mavlink.MAVLink_message:
    return mavlink.MAVLink_autopilot_version_message(
        AUTOPILOT_CAPABILITIES, PX4_FLIGHT_SW_VERSION, 0, 0, 0, [0] * 8, [0] * 8, [0] * 8, 0x26AC, 0x0011,
        v.system_id, [0] * 18,
    )


def statustext(severity: int, text: str) -> mavlink.MAVLink_message:
    """STATUSTEXT with ``text`` cut to MAVLink's 50 characters."""
    return mavlink.MAVLink_statustext_message(severity, text.encode("ascii", "replace")[:50])


def _wrap_pi(angle_rad: float) -> float:
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi


BUILDERS: dict[str, Callable[[Vehicle, float], mavlink.MAVLink_message | None]] = {
    "HEARTBEAT": heartbeat,
    "SYS_STATUS": sys_status,
    "LOCAL_POSITION_NED": local_position_ned,
    "GLOBAL_POSITION_INT": global_position_int,
    "GPS_RAW_INT": gps_raw_int,
    "EXTENDED_SYS_STATE": extended_sys_state,
    "HOME_POSITION": home_position,
    "ATTITUDE": attitude,
    "ALTITUDE": altitude,
    "VFR_HUD": vfr_hud,
    "DISTANCE_SENSOR": distance_sensor,
    "BATTERY_STATUS": battery_status,
    "POSITION_TARGET_LOCAL_NED": position_target_local_ned,
    "AUTOPILOT_VERSION": autopilot_version,
}

BUILDER_BY_ID: dict[int, str] = {
    getattr(mavlink, f"MAVLINK_MSG_ID_{name}"): name for name in BUILDERS
}
