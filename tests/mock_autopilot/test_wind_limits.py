"""The mock's wind estimate (WIND_COV) and PX4's COM_WIND_WARN / COM_WIND_MAX rules."""

from __future__ import annotations

import math

import numpy as np

from mission_plan.dynamics import KinematicLimits
from mission_plan.weather import SensorSpec, WindSpec
from mock_autopilot import telemetry
from mock_autopilot.backends.interface import VehicleRequest
from mock_autopilot.backends.px4 import Px4Backend, px4_vehicle_configs
from mock_autopilot.commander import arming_denial
from mock_autopilot.vehicle import Vehicle, VehicleConfig
from mock_autopilot.vehicle_snapshot import take_snapshot
from mock_autopilot.weather_model import Weather

STEADY = Weather(WindSpec(speed_mps=6.0, from_deg=270.0), SensorSpec(gps_white_sigma_m=0.3, altitude_sigma_m=0.2))


def _hovering(params: dict[str, float]) -> Px4Backend:
    backend = Px4Backend(px4_vehicle_configs(KinematicLimits(), 10.0, [(0.0, 0.0)], weather=STEADY, params=params))
    backend.hover_start(10.0)
    return backend


def _fly(backend: Px4Backend, seconds: float) -> None:
    for _ in range(int(seconds / 0.05)):
        backend.step(np.zeros((1, 3)), np.zeros(1), np.array([True]), [VehicleRequest.NONE], 0.05)


def test_wind_cov_reports_the_estimate_and_gps_raw_int_the_accuracy() -> None:
    backend = _hovering({})
    _fly(backend, 20.0)
    vehicle = backend.vehicles[0]
    snapshot = take_snapshot(vehicle, vehicle.t_s)
    wind = telemetry.wind_cov(snapshot)
    assert wind.get_type() == "WIND_COV"
    assert math.hypot(wind.wind_x, wind.wind_y) > 4.5 and abs(wind.wind_y) > abs(wind.wind_x)  # toward the east
    assert math.isnan(wind.wind_z)
    gps = telemetry.gps_raw_int(snapshot)
    assert (gps.eph, gps.epv) == (30, 20)


def test_warning_above_com_wind_warn_once_a_minute() -> None:
    backend = _hovering({"COM_WIND_WARN": 3.0})
    _fly(backend, 30.0)
    warnings = [t for t in backend.texts(0) if t.startswith("High wind speed detected")]
    assert len(warnings) == 1 and ", landing advis" in warnings[0]  # STATUSTEXT holds 50 characters
    assert backend.state().flight_mode[0] == "OFFBOARD"


def test_above_com_wind_max_the_vehicle_returns_and_arming_is_refused() -> None:
    backend = _hovering({})
    backend.vehicles[0].params.set("COM_WIND_MAX", 4.0)
    _fly(backend, 2.0)
    assert backend.state().flight_mode[0] == "AUTO.RTL"
    assert any("wind speed above limit" in t for t in backend.texts(0))
    grounded = Vehicle(VehicleConfig(0, params={"COM_WIND_MAX": 4.0}, weather=STEADY))
    assert grounded.weather is not None
    grounded.weather.wind_estimate_ned_mps = np.array([[0.0, 6.0, 0.0]])
    assert arming_denial(grounded, 0.0) == "Wind speed is above limit (6.0 m/s)"


def test_no_limits_by_default() -> None:
    backend = _hovering({})
    _fly(backend, 10.0)
    assert backend.state().flight_mode[0] == "OFFBOARD"
    assert not any("wind" in t.lower() for t in backend.texts(0))


def test_altitude_noise_on_the_ground_is_no_take_off() -> None:
    """An armed vehicle that never left its pad is disarmed by the preflight timer, not "by landing", however its
    barometer wanders (the take-off and the ground contact are the body's)."""
    from mock_autopilot.commander import arm

    vehicle = Vehicle(VehicleConfig(0, weather=Weather(WindSpec(), SensorSpec(altitude_sigma_m=0.4), seed=2)))
    arm(vehicle, 0.0)
    texts = []
    for k in range(1, 300):
        texts += [o.message.text for o in vehicle.tick(k * 0.05) if o.message.get_type() == "STATUSTEXT"]
    assert not vehicle.took_off and not vehicle.armed
    assert any("preflight" in str(t) for t in texts) and not any("landing" in str(t) for t in texts)


def test_armed_in_hold_on_the_ground_a_noisy_barometer_never_reads_airborne() -> None:
    """PX4 keeps an armed multicopter at idle on the ground in Hold until a take-off: the land detector keeps saying
    "on ground", so a client (MAVSDK's in_air) sends its take-off; before, holding the noisy altitude estimate
    lifted the body and the vehicle reported itself in the air."""
    from mock_autopilot.commander import arm
    from comms.px4 import LandedState

    vehicle = Vehicle(VehicleConfig(0, weather=Weather(WindSpec(speed_mps=5.0), SensorSpec(altitude_sigma_m=0.2),
                                                       seed=3)))
    for k in range(1, 40):
        vehicle.tick(k * 0.05)
    arm(vehicle, 2.0)
    states = []
    for k in range(41, 200):
        vehicle.tick(k * 0.05)
        states.append(vehicle.landed_state)
    assert vehicle.armed and vehicle.on_ground()
    assert set(states) == {LandedState.ON_GROUND}
