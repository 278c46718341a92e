"""The simulated relative-position sensor: range limit, body frame, seeded noise of the specified σ."""

from __future__ import annotations

import math

import numpy as np
import pytest

from comms.frames import body_fr_to_en
from comms.messages import NeighbourRanging, decode, encode
from mission_plan.weather import SensorSpec
from mock_autopilot.relative_ranging import neighbour_ranging

POSITIONS = np.array([[0.0, 0.0], [10.0, 0.0], [0.0, -20.0], [30.0, 0.0], [np.nan, np.nan]])
IDS = [1, 2, 3, 4, 5]


def test_only_living_vehicles_in_range_are_measured_in_the_body_frame() -> None:
    spec = SensorSpec(ranging_sigma_m=0.0, ranging_range_m=25.0)
    yaw = math.radians(90.0)
    msg = neighbour_ranging(2.0, 0, IDS, POSITIONS, np.full(5, yaw), spec, seed=1)
    assert msg.vehicle_id == 1 and msg.t_s == 2.0
    assert msg.neighbour_ids == [2, 3]
    # Facing east: the drone 10 m east is straight ahead, the one 20 m south on its right.
    assert np.allclose(msg.forward_right_m, [(10.0, 0.0), (0.0, 20.0)])
    assert np.allclose(body_fr_to_en(np.array(msg.forward_right_m), yaw), POSITIONS[[1, 2]])


def test_noise_has_the_specified_sigma_and_comes_from_the_seed() -> None:
    spec = SensorSpec(ranging_sigma_m=0.1, ranging_range_m=25.0)
    yaws = np.zeros(5)
    samples = np.array([neighbour_ranging(0.1 * k, 0, IDS, POSITIONS, yaws, spec, seed=7).forward_right_m
                        for k in range(2000)])
    errors = samples - np.array([(0.0, 10.0), (-20.0, 0.0)])
    assert errors.std() == pytest.approx(0.1, rel=0.05)
    assert abs(errors.mean()) < 0.01
    again = neighbour_ranging(0.3, 0, IDS, POSITIONS, yaws, spec, seed=7)
    assert again == neighbour_ranging(0.3, 0, IDS, POSITIONS, yaws, spec, seed=7)
    assert again != neighbour_ranging(0.3, 0, IDS, POSITIONS, yaws, spec, seed=8)


def test_the_message_round_trips_and_a_bad_one_is_dropped() -> None:
    msg = neighbour_ranging(1.0, 0, IDS, POSITIONS, np.zeros(5), SensorSpec(), seed=1)
    assert decode(NeighbourRanging, encode(msg)) == msg
    bad = encode(NeighbourRanging(vehicle_id=1, t_s=1.0, neighbour_ids=[2], forward_right_m=[(1.0, 2.0)]))
    assert decode(NeighbourRanging, bad.replace(b"\x91\x02", b"\x92\x02\x03")) is None
