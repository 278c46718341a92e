"""Outgoing telemetry: one pure encoder per streamed message, from a frozen snapshot of the vehicle.

The vehicle takes a :class:`VehicleSnapshot` once per tick that has something due, and every builder reads only
that snapshot, so a builder can neither change the vehicle nor see it half-updated, and links that send the same
stream in one tick share one message. A builder returns None when PX4 would not send its message (no
GLOBAL_POSITION_INT without a global position, no HOME_POSITION before home is set). Contents follow
PX4_INTERFACE.md; the SYS_STATUS bits are the ones MAVSDK's telemetry health reads: GPS present+healthy ->
is_global_position_ok; VISION_POSITION (our odometry, every vehicle has it) -> is_local_position_ok; PREARM_CHECK
healthy -> is_armable.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Callable, NamedTuple

import numpy as np
from pymavlink.dialects.v20 import common as mavlink

from comms.frames import GeodeticHome, enu_to_geodetic, local_ned_to_mission_enu
from comms.px4 import LandedState, Px4Mode, base_mode, custom_mode
from mock_autopilot.rangefinder import distance_sensor_message
from mock_autopilot.setpoints import OffboardSetpoint

MAV_TYPE_QUADROTOR = mavlink.MAV_TYPE_QUADROTOR
MAV_AUTOPILOT_PX4 = mavlink.MAV_AUTOPILOT_PX4
MAV_STATE_STANDBY = mavlink.MAV_STATE_STANDBY
MAV_STATE_ACTIVE = mavlink.MAV_STATE_ACTIVE
MAV_STATE_CRITICAL = mavlink.MAV_STATE_CRITICAL
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


DEFAULT_EPH_CM = 80
DEFAULT_EPV_CM = 120
"""GPS_RAW_INT accuracies of a good fix [cm] when the sensors are exact."""


class VehicleSnapshot(NamedTuple):
    """Everything telemetry reports about one vehicle at one simulated time.

    position_ned_m / velocity_ned_mps / home_ned_m [m, m/s; local NED from the pad], yaw_rad and roll/pitch
    [rad], pad_enu_m [m; mission ENU from ``home``], battery fields in MAVLink's units of choice below.
    """

    t_s: float
    time_boot_ms: int
    system_id: int
    mode: Px4Mode
    armed: bool
    failsafe: bool
    prearm_ok: bool
    has_gps: bool
    global_position_valid: bool
    landed_state: LandedState
    position_ned_m: tuple[float, float, float]
    velocity_ned_mps: tuple[float, float, float]
    yaw_rad: float
    yaw_rate_rad_s: float
    roll_rad: float
    pitch_rad: float
    home_valid: bool
    home_ned_m: tuple[float, float, float]
    home: GeodeticHome
    pad_enu_m: tuple[float, float, float]
    ground_below_enu_m: float
    """Ground height below the vehicle above the home ground [m] (the rangefinder's ground)."""
    battery_remaining: float
    battery_voltage_v: float
    battery_current_a: float
    battery_consumed_mah: float
    battery_charge_state: int
    """MAV_BATTERY_CHARGE_STATE: 1 ok, 2 low, 3 critical, 4 emergency."""
    offboard_setpoint: OffboardSetpoint | None
    eph_cm: int = DEFAULT_EPH_CM
    """GPS horizontal / vertical accuracy [cm] reported in GPS_RAW_INT."""
    epv_cm: int = DEFAULT_EPV_CM
    wind_ned_mps: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """The estimator's wind [m/s NED] (WIND_COV)."""
    wind_variance_m2s2: float = 0.0

    @property
    def geodetic(self) -> tuple[float, float, float]:
        """(lat_deg, lon_deg, alt_m AMSL) of the vehicle: home + pad + local position."""
        return geodetic_of(self.position_ned_m, self.pad_enu_m, self.home)

    @property
    def home_geodetic(self) -> tuple[float, float, float]:
        """(lat_deg, lon_deg, alt_m AMSL) of the home position."""
        return geodetic_of(self.home_ned_m, self.pad_enu_m, self.home)

    @property
    def amsl_m(self) -> float:
        """Altitude above mean sea level [m]."""
        return self.home.alt_m + float(self.pad_enu_m[2]) - self.position_ned_m[2]


@lru_cache(maxsize=4096)
def geodetic_of(position_ned_m: tuple[float, float, float], pad_enu_m: tuple[float, float, float],
                home: GeodeticHome) -> tuple[float, float, float]:
    """(lat_deg, lon_deg, alt_m AMSL) of a vehicle's local NED position (home + pad + local). Remembered: a vehicle
    at rest, and the GLOBAL_POSITION_INT and GPS_RAW_INT of one tick, convert once."""
    enu = local_ned_to_mission_enu(np.asarray(position_ned_m), pad_enu_m)
    lat, lon, alt = enu_to_geodetic(enu, home)
    return float(lat), float(lon), float(alt)


def _i16(value: float) -> int:
    return int(max(-32768, min(32767, round(value))))


def heartbeat(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    if s.failsafe:
        status = MAV_STATE_CRITICAL
    else:
        status = MAV_STATE_ACTIVE if s.armed else MAV_STATE_STANDBY
    return mavlink.MAVLink_heartbeat_message(
        MAV_TYPE_QUADROTOR, MAV_AUTOPILOT_PX4, base_mode(s.mode, s.armed), custom_mode(s.mode), status, 3
    )


def sys_status(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    present = _BASE_SENSORS | (mavlink.MAV_SYS_STATUS_SENSOR_GPS if s.has_gps else 0)
    health = present
    if not s.global_position_valid:
        health &= ~mavlink.MAV_SYS_STATUS_SENSOR_GPS
    if not s.prearm_ok:
        health &= ~mavlink.MAV_SYS_STATUS_PREARM_CHECK
    if s.battery_charge_state >= 3:
        health &= ~mavlink.MAV_SYS_STATUS_SENSOR_BATTERY
    return mavlink.MAVLink_sys_status_message(
        present, present, health, 200, int(s.battery_voltage_v * 1000), int(s.battery_current_a * 100),
        int(round(s.battery_remaining * 100)), 0, 0, 0, 0, 0, 0,
    )


def local_position_ned(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    p, vel = s.position_ned_m, s.velocity_ned_mps
    return mavlink.MAVLink_local_position_ned_message(s.time_boot_ms, p[0], p[1], p[2], vel[0], vel[1], vel[2])


def global_position_int(s: VehicleSnapshot) -> mavlink.MAVLink_message | None:
    if not s.global_position_valid:
        return None
    lat, lon, alt = s.geodetic
    vel = s.velocity_ned_mps
    heading_cdeg = int(round(math.degrees(s.yaw_rad) * 100)) % 36000
    relative_m = -s.position_ned_m[2] + s.home_ned_m[2]
    return mavlink.MAVLink_global_position_int_message(
        s.time_boot_ms, int(round(lat * 1e7)), int(round(lon * 1e7)), int(round(alt * 1000)),
        int(round(relative_m * 1000)), _i16(vel[0] * 100), _i16(vel[1] * 100), _i16(vel[2] * 100), heading_cdeg,
    )


def gps_raw_int(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    usec = int(s.t_s * 1e6)
    if not s.global_position_valid:
        fix = 1 if s.has_gps else 0
        return mavlink.MAVLink_gps_raw_int_message(usec, fix, 0, 0, 0, 65535, 65535, 65535, 65535, 0)
    lat, lon, alt = s.geodetic
    vel = s.velocity_ned_mps
    ground_speed = math.hypot(vel[0], vel[1])
    cog = int(round(math.degrees(math.atan2(vel[1], vel[0])) * 100)) % 36000
    return mavlink.MAVLink_gps_raw_int_message(
        usec, 3, int(round(lat * 1e7)), int(round(lon * 1e7)), int(round(alt * 1000)), s.eph_cm, s.epv_cm,
        int(round(ground_speed * 100)), cog, 12,
    )


def wind_cov(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    """The estimator's wind as PX4 sends it: north and east components, the horizontal variance, no vertical
    estimate (NaN) and the altitude it holds at."""
    w = s.wind_ned_mps
    return mavlink.MAVLink_wind_cov_message(
        int(s.t_s * 1e6), w[0], w[1], math.nan, s.wind_variance_m2s2, math.nan, s.amsl_m, math.nan, math.nan)


def extended_sys_state(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    return mavlink.MAVLink_extended_sys_state_message(0, int(s.landed_state))


def home_position(s: VehicleSnapshot) -> mavlink.MAVLink_message | None:
    if not s.home_valid:
        return None
    lat, lon, alt = s.home_geodetic
    h = s.home_ned_m
    return mavlink.MAVLink_home_position_message(
        int(round(lat * 1e7)), int(round(lon * 1e7)), int(round(alt * 1000)), h[0], h[1], h[2],
        [1.0, 0.0, 0.0, 0.0], 0.0, 0.0, 0.0, int(s.t_s * 1e6),
    )


def attitude(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    return mavlink.MAVLink_attitude_message(
        s.time_boot_ms, s.roll_rad, s.pitch_rad, float(_wrap_pi(s.yaw_rad)), 0.0, 0.0, s.yaw_rate_rad_s
    )


def altitude(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    local_up = -s.position_ned_m[2]
    amsl = s.amsl_m
    home_up = -s.home_ned_m[2]
    return mavlink.MAVLink_altitude_message(int(s.t_s * 1e6), amsl, amsl, local_up, local_up - home_up, math.nan, local_up)


def vfr_hud(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    vel = s.velocity_ned_mps
    speed = float(math.hypot(vel[0], vel[1]))
    heading = int(round(math.degrees(s.yaw_rad))) % 360
    throttle = 50 if s.armed and s.landed_state != LandedState.ON_GROUND else 0
    return mavlink.MAVLink_vfr_hud_message(speed, speed, heading, throttle, s.amsl_m, -vel[2])


def distance_sensor(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    """The downward rangefinder: mission up (pad height + local up) minus the ground below (``rangefinder.py``)."""
    return distance_sensor_message(s.time_boot_ms, s.pad_enu_m[2] - s.position_ned_m[2] - s.ground_below_enu_m)


def battery_status(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    voltages = [int(s.battery_voltage_v * 1000)] + [65535] * 9
    return mavlink.MAVLink_battery_status_message(
        0, 0, 1, 32767, voltages, int(s.battery_current_a * 100), int(s.battery_consumed_mah), -1,
        int(round(s.battery_remaining * 100)), 0, s.battery_charge_state, [0, 0, 0, 0], 0, 0,
    )


def position_target_local_ned(s: VehicleSnapshot) -> mavlink.MAVLink_message | None:
    sp = s.offboard_setpoint
    if sp is None:
        return None
    return mavlink.MAVLink_position_target_local_ned_message(
        s.time_boot_ms, mavlink.MAV_FRAME_LOCAL_NED, sp.type_mask, *sp.position_ned_m, *sp.velocity_ned_mps,
        *sp.acceleration_ned_mps2, sp.yaw_rad, sp.yaw_rate_rad_s,
    )


def autopilot_version(s: VehicleSnapshot) -> mavlink.MAVLink_message:
    return mavlink.MAVLink_autopilot_version_message(
        AUTOPILOT_CAPABILITIES, PX4_FLIGHT_SW_VERSION, 0, 0, 0, [0] * 8, [0] * 8, [0] * 8, 0x26AC, 0x0011,
        s.system_id, [0] * 18,
    )


def statustext(severity: int, text: str) -> mavlink.MAVLink_message:
    """STATUSTEXT with ``text`` cut to MAVLink's 50 characters."""
    return mavlink.MAVLink_statustext_message(severity, text.encode("ascii", "replace")[:50])


def _wrap_pi(angle_rad: float) -> float:
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi


BUILDERS: dict[str, Callable[[VehicleSnapshot], mavlink.MAVLink_message | None]] = {
    "HEARTBEAT": heartbeat,
    "SYS_STATUS": sys_status,
    "LOCAL_POSITION_NED": local_position_ned,
    "GLOBAL_POSITION_INT": global_position_int,
    "GPS_RAW_INT": gps_raw_int,
    "EXTENDED_SYS_STATE": extended_sys_state,
    "HOME_POSITION": home_position,
    "ATTITUDE": attitude,
    "WIND_COV": wind_cov,
    "ALTITUDE": altitude,
    "VFR_HUD": vfr_hud,
    "DISTANCE_SENSOR": distance_sensor,
    "DISTANCE_SENSOR": distance_sensor,
    "BATTERY_STATUS": battery_status,
    "POSITION_TARGET_LOCAL_NED": position_target_local_ned,
    "AUTOPILOT_VERSION": autopilot_version,
}

BUILDER_BY_ID: dict[int, str] = {
    getattr(mavlink, f"MAVLINK_MSG_ID_{name}"): name for name in BUILDERS
}
