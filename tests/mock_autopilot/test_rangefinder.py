"""DISTANCE_SENSOR: the downward rangefinder's encoding, the vehicle's stream, and the ground it measures."""

from __future__ import annotations

import math

import numpy as np
from pymavlink.dialects.v20 import common as mavlink

from mock_autopilot import telemetry
from mock_autopilot.kinematics import KinematicState
from mock_autopilot.px4_streams import ONBOARD, stream_periods_s
from mock_autopilot.rangefinder import MAX_DISTANCE_M, MIN_DISTANCE_M, distance_sensor_message
from mock_autopilot.vehicle import Vehicle, VehicleConfig
from mock_autopilot.vehicle_snapshot import take_snapshot
from mock_autopilot.world.flood_model import ExpandingCircle
from mock_autopilot.world.ground import height_above_ground_m, relative_ground_m


def _roundtrip(message: mavlink.MAVLink_message) -> mavlink.MAVLink_message:
    codec = mavlink.MAVLink(None, srcSystem=1, srcComponent=1)
    return codec.parse_char(message.pack(codec))


def test_a_downward_laser_reading_in_centimetres_clamped_to_its_range() -> None:
    msg = _roundtrip(distance_sensor_message(1234, 9.37))
    assert msg.get_type() == "DISTANCE_SENSOR" and msg.time_boot_ms == 1234
    assert msg.current_distance == 937
    assert msg.orientation == mavlink.MAV_SENSOR_ROTATION_PITCH_270
    assert msg.type == mavlink.MAV_DISTANCE_SENSOR_LASER
    assert (msg.min_distance, msg.max_distance) == (round(MIN_DISTANCE_M * 100), round(MAX_DISTANCE_M * 100))
    assert _roundtrip(distance_sensor_message(0, -3.0)).current_distance == msg.min_distance
    assert _roundtrip(distance_sensor_message(0, 500.0)).current_distance == msg.max_distance
    assert _roundtrip(distance_sensor_message(0, math.nan)).current_distance == msg.max_distance


def test_the_vehicle_reports_its_height_above_the_ground_below_it() -> None:
    v = Vehicle(VehicleConfig(instance=0))
    v.body = KinematicState(position_ned_m=np.array([0.0, 0.0, -10.0]))
    assert telemetry.distance_sensor(take_snapshot(v, 1.0)).current_distance == 1000
    v.ground_below_enu_m = 1.5  # a rise under the drone: the ground is nearer
    assert telemetry.distance_sensor(take_snapshot(v, 1.0)).current_distance == 850
    assert math.isclose(stream_periods_s("px4", ONBOARD)["DISTANCE_SENSOR"], 0.1)  # PX4 onboard mode: 10 Hz


class _Slope:
    """Ground rising 0.1 m per metre east: a flood with relief."""

    def ground_height_m(self, points_en_m: np.ndarray) -> np.ndarray:
        return 5.0 + 0.1 * np.asarray(points_en_m, float)[..., 0]


def test_height_above_ground_is_relative_to_the_ground_at_home() -> None:
    assert height_above_ground_m(ExpandingCircle(), (30.0, 4.0, 10.0)) == 10.0  # flat models: up
    assert np.allclose(relative_ground_m(_Slope(), np.array([[0.0, 0.0], [20.0, 3.0]])), [0.0, 2.0])
    assert math.isclose(height_above_ground_m(_Slope(), (20.0, 3.0, 10.0)), 8.0)
