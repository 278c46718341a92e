"""The collision barrier keeps clear of neighbours where the relative-position sensor sees them."""

from __future__ import annotations

import math

import numpy as np

from comms.messages import NeighbourRanging
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.safety import collision_barrier, sensed_positions_en_m
from vehicle_agents.control.types import NeighbourInfo, SensedOffsets
from vehicle_agents.core.sensed_neighbours import MAX_RANGING_AGE_S, reads_ranging, sensed_offsets

IMPROVED = ControlParams(mode="improved", sensed_barrier=True, cooperative_position=True, ranging_available=True,
                         odometry_drift_frac=0.01)


def test_who_reads_the_sensor() -> None:
    assert reads_ranging(IMPROVED, has_gps=True) and reads_ranging(IMPROVED, has_gps=False)
    assert not reads_ranging(ControlParams(mode="improved", sensed_barrier=True, ranging_available=False), False)
    paper = ControlParams(mode="paper", ranging_available=True, odometry_drift_frac=0.01)
    assert not reads_ranging(paper, has_gps=False)
    only_correction = ControlParams(mode="improved", cooperative_position=True, ranging_available=True,
                                    odometry_drift_frac=0.01)
    assert reads_ranging(only_correction, has_gps=False) and not reads_ranging(only_correction, has_gps=True)


def test_offsets_are_turned_into_the_mission_frame_by_the_heading() -> None:
    ranging = NeighbourRanging(vehicle_id=1, t_s=10.0, neighbour_ids=[2, 3], forward_right_m=[(2.0, 0.0), (0.0, 1.0)])
    facing_north = sensed_offsets(ranging, 0.0, 10.05)
    assert facing_north is not None and math.isclose(facing_north.age_s, 0.05)
    assert facing_north.neighbour_ids == (2, 3)
    assert np.allclose(facing_north.offsets_en_m, [[0.0, 2.0], [1.0, 0.0]])
    facing_east = sensed_offsets(ranging, math.pi / 2.0, 10.0)
    assert facing_east is not None and np.allclose(facing_east.offsets_en_m[0], [2.0, 0.0])


def test_an_old_or_empty_measurement_is_not_used() -> None:
    ranging = NeighbourRanging(vehicle_id=1, t_s=10.0, neighbour_ids=[2], forward_right_m=[(2.0, 0.0)])
    assert sensed_offsets(ranging, 0.0, 10.0 + MAX_RANGING_AGE_S + 0.01) is None
    assert sensed_offsets(None, 0.0, 10.0) is None
    nobody = NeighbourRanging(vehicle_id=1, t_s=10.0, neighbour_ids=[], forward_right_m=[])
    assert sensed_offsets(nobody, 0.0, 10.0) is None


def test_a_neighbour_believed_far_but_sensed_close_is_kept_clear_of() -> None:
    """Two boundary drones launched 2.0 m apart; this one's GPS fix is 1.5 m off, so the other's broadcast puts it
    3.5 m east. Commanded east at 1 m/s, the barrier on the broadcast lets it close; on the sensor it backs off."""
    own = np.array([0.0, 0.0])
    believed = NeighbourInfo(2, "boundary", np.array([3.5, 0.0]), np.zeros(2), 10.0)
    sensed = SensedOffsets((2,), np.array([[2.0, 0.0]]), age_s=0.05)
    command = np.array([1.0, 0.0])
    on_broadcast = collision_barrier("boundary", command, own, [believed], IMPROVED)
    placed = sensed_positions_en_m([believed], own, np.zeros(2), sensed)
    on_sensor = collision_barrier("boundary", command, own, [believed], IMPROVED, placed)
    assert on_broadcast[0] > 0.5
    assert on_sensor[0] < 0.0
    assert np.allclose(placed, [[2.0, 0.0]])


def test_placing_by_the_sensor_counts_both_drones_motion_since_the_measurement() -> None:
    believed = NeighbourInfo(2, "boundary", np.array([9.0, 9.0]), np.array([0.0, 1.0]), 10.0)
    unseen = NeighbourInfo(3, "follower", np.array([-4.0, 0.0]), np.array([1.0, 0.0]), 10.0, age_s=0.2)
    placed = sensed_positions_en_m([believed, unseen], np.array([1.0, 0.0]), np.array([2.0, 0.0]),
                                   SensedOffsets((7, 2), np.array([[0.0, -5.0], [3.0, 0.0]]), age_s=0.1))
    assert np.allclose(placed, [[3.8, 0.1], [-3.8, 0.0]])
