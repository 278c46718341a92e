"""The frozen view of a vehicle that telemetry encodes (:class:`~mock_autopilot.telemetry.VehicleSnapshot`)."""

from __future__ import annotations

from mock_autopilot.commander import arming_denial
from mock_autopilot.telemetry import VehicleSnapshot
from mock_autopilot.vehicle_state import VehicleState


def take_snapshot(v: VehicleState, now_s: float) -> VehicleSnapshot:
    """Copy what telemetry reports out of the vehicle's state at simulated time ``now_s``."""
    p, vel, home = v.position_ned_m, v.velocity_ned_mps, v.home_ned_m
    roll, pitch = v.tilt_rad()
    return VehicleSnapshot(
        t_s=now_s, time_boot_ms=int(max(0.0, now_s - v.boot_time_s) * 1000.0) & 0xFFFFFFFF,
        system_id=v.system_id, mode=v.mode, armed=v.armed, failsafe=v.failsafe,
        prearm_ok=arming_denial(v, now_s) is None, has_gps=v.config.has_gps,
        global_position_valid=v.global_position_valid, landed_state=v.landed_state,
        position_ned_m=(float(p[0]), float(p[1]), float(p[2])),
        velocity_ned_mps=(float(vel[0]), float(vel[1]), float(vel[2])),
        yaw_rad=v.reported_yaw_rad, yaw_rate_rad_s=float(v.yaw_rate_rad_s), roll_rad=roll, pitch_rad=pitch,
        home_valid=v.home_valid, home_ned_m=(float(home[0]), float(home[1]), float(home[2])),
        home=v.config.home, pad_enu_m=v.config.pad_enu_m, ground_below_enu_m=v.ground_below_enu_m,
        battery_remaining=v.battery.remaining,
        battery_voltage_v=v.battery.voltage_v(), battery_current_a=v.battery.current_a(v.armed),
        battery_consumed_mah=v.battery.consumed_mah, battery_charge_state=v.battery.charge_state(v.params),
        offboard_setpoint=v.offboard_setpoint,
        **_weather_fields(v),
    )


def _weather_fields(v: VehicleState) -> dict[str, object]:
    """GPS accuracy and the wind estimate, where the vehicle flies in weather (defaults otherwise)."""
    if v.weather is None:
        return {}
    sensors = v.weather.weather.sensors
    wind = v.wind_estimate_ned_mps
    fields: dict[str, object] = {
        "wind_ned_mps": (float(wind[0]), float(wind[1]), float(wind[2])),
        "wind_variance_m2s2": 2.0 * v.weather.scales.sigma_uv_mps ** 2,
    }
    if not sensors.exact:
        fields["eph_cm"] = max(1, int(round(sensors.eph_m * 100.0)))
        fields["epv_cm"] = max(1, int(round(sensors.altitude_sigma_m * 100.0)))
    return fields
