"""The improved mode's collision barrier: braking-aware, and fed with neighbours carried forward by their age."""

import numpy as np
import pytest

from mock_autopilot.kinematics import KinematicLimits, KinematicState, step_kinematics
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.safety import (
    braking_horizon_m,
    collision_barrier,
    predicted_positions_en_m,
    safety_filter,
    stopping_speed_mps,
)
from vehicle_agents.control.types import NeighbourInfo


@pytest.mark.parametrize("gap_m", [0.1, 1.0, 2.5, 10.0])
def test_stopping_speed_uses_the_whole_gap(gap_m: float) -> None:
    v = stopping_speed_mps(gap_m, braking_mps2=2.0, reaction_s=0.5)
    assert v * 0.5 + v * v / (2.0 * 2.0) == pytest.approx(gap_m)
    assert braking_horizon_m(2.5, v, 2.0, 0.5) == pytest.approx(2.5 + gap_m)


def test_no_gap_no_approach() -> None:
    assert stopping_speed_mps(0.0, 2.0, 0.5) == 0.0 and stopping_speed_mps(-1.0, 2.0, 0.5) == 0.0


def test_neighbours_are_carried_forward_by_their_age_up_to_a_cap() -> None:
    fresh = NeighbourInfo(1, "boundary", np.array([0.0, 0.0]), np.array([4.0, 0.0]), 10.0, age_s=0.0)
    late = NeighbourInfo(2, "boundary", np.array([0.0, 0.0]), np.array([4.0, 0.0]), 10.0, age_s=0.25)
    ancient = NeighbourInfo(3, "boundary", np.array([0.0, 0.0]), np.array([0.0, -2.0]), 10.0, age_s=5.0)
    predicted = predicted_positions_en_m([fresh, late, ancient], horizon_cap_s=1.0)
    assert np.allclose(predicted, [[0.0, 0.0], [1.0, 0.0], [0.0, -2.0]])


def _head_on_min_distance(braking_mps2: float, radius_m: float) -> float:
    """A drone commanded at 5 m/s straight at one flying at 3 m/s towards it (8 m/s closing), through PX4-like
    kinematics (3 m/s², 0.3 s response) at 20 Hz, hearing the other 0.15 s late and carrying it forward."""
    params = ControlParams(mode="improved")
    limits = KinematicLimits()
    dt_s, delay_steps = 0.05, 3
    me = KinematicState(np.array([0.0, 0.0, -10.0]), np.array([0.0, 5.0, 0.0]))  # NED: flying east
    other_x, other_v = 40.0, -3.0
    history = [(other_x, other_v)] * delay_steps
    closest = np.inf
    for _ in range(400):
        heard_x, heard_v = history[-delay_steps]
        neighbour = NeighbourInfo(2, "boundary", np.array([heard_x, 0.0]), np.array([heard_v, 0.0]), 10.0,
                                  age_s=delay_steps * dt_s)
        command = safety_filter(np.array([5.0, 0.0]), me.position_ned_m[[1, 0]], predicted_positions_en_m([neighbour]),
                                params.safety_min_distance_m, radius_m, params.safety_closing_rate_per_s,
                                np.array([[heard_v, 0.0]]), braking_mps2=braking_mps2,
                                reaction_s=params.safety_reaction_s)
        me = step_kinematics(me, np.array([command[1], command[0], 0.0]), limits, dt_s)
        other_x += other_v * dt_s
        if other_x - me.position_ned_m[1] < 8.0:
            other_v = 0.0  # the other stops short, as a boundary drone reaching its ring slot does
        history.append((other_x, other_v))
        closest = min(closest, other_x - float(me.position_ned_m[1]))
    return closest


def test_braking_barrier_keeps_a_head_on_approach_clear_of_the_minimum() -> None:
    params = ControlParams(mode="improved")
    horizon_m = braking_horizon_m(params.safety_min_distance_m, 2 * params.max_speed_mps, params.safety_braking_mps2,
                                  params.safety_reaction_s)
    closest_m = _head_on_min_distance(params.safety_braking_mps2, horizon_m)
    assert closest_m >= 0.8 * params.safety_min_distance_m


def test_a_barrier_switched_on_only_5_m_out_acts_too_late() -> None:
    """The case the braking horizon exists for: a linear barrier that looks 5 m out cannot stop 8 m/s closing."""
    params = ControlParams(mode="improved")
    assert _head_on_min_distance(0.0, params.safety_radius_m) < 0.5 * params.safety_min_distance_m


def test_boxed_in_inside_the_minimum_the_barrier_closes_on_nobody() -> None:
    """Launch crowd: neighbours north (1.4 m), south (2.25 m) and west (1.4 m), all inside the 2.5 m minimum. Moving
    away from all of them at once is impossible; the command must at least close on none of them."""
    others = np.array([[0.0, 1.42], [0.0, -2.25], [-1.38, -0.2]])
    v = safety_filter(np.array([2.9, -2.1]), np.zeros(2), others, 2.5, 32.5, 1.0, np.zeros((3, 2)),
                      braking_mps2=2.0, reaction_s=0.5)
    towards = others / np.hypot(others[:, 0], others[:, 1])[:, None]
    assert np.all(towards @ v <= 1e-9)
    assert v[0] > 2.0  # east, the free side, is still open



def test_a_leader_told_off_by_a_boundary_drone_does_not_run_over_a_follower() -> None:
    """Launch crowd: a boundary drone 2 m west (inside the 2.5 m it is owed: move east) and a follower 1.3 m east
    (just outside the 1.25 m last resort). The two demands contradict; the leader must not close on the follower."""
    params = ControlParams(mode="improved")
    boundary = NeighbourInfo(1, "boundary", np.array([-2.0, 0.0]), np.zeros(2), 10.0)
    follower = NeighbourInfo(11, "follower", np.array([1.3, 0.0]), np.zeros(2), 10.0)
    v = collision_barrier("leader", np.zeros(2), np.zeros(2), [boundary, follower], params)
    gap_m = 1.3 - 0.5 * params.safety_min_distance_m
    assert v[0] <= params.safety_closing_rate_per_s * gap_m + 1e-9
    alone = collision_barrier("leader", np.zeros(2), np.zeros(2), [boundary], params)
    assert alone[0] > v[0]  # without the follower the leader does move east, away from the boundary drone


def test_the_barrier_leaves_a_command_clear_of_everyone_unchanged() -> None:
    params = ControlParams(mode="improved")
    heard = [NeighbourInfo(1, "boundary", np.array([-8.0, 0.0]), np.zeros(2), 10.0),
             NeighbourInfo(11, "follower", np.array([0.0, 9.0]), np.zeros(2), 10.0)]
    command = np.array([0.5, -0.3])
    assert np.array_equal(collision_barrier("leader", command, np.zeros(2), heard, params), command)


def test_a_follower_pushed_by_a_peer_does_not_run_into_the_leader() -> None:
    """A follower 3.4 m behind the stationary leader, a peer 2.1 m behind it closing at 3 m/s (inside the 3 m
    minimum): the follower does not flee the peer into the leader."""
    params = ControlParams(mode="improved", safety_min_distance_m=3.0)
    leader = NeighbourInfo(33, "leader", np.array([3.4, 0.0]), np.zeros(2), 10.0)
    peer = NeighbourInfo(63, "follower", np.array([-2.1, 0.0]), np.array([3.0, 0.0]), 10.0)
    v = collision_barrier("follower", np.array([3.9, 0.0]), np.zeros(2), [leader, peer], params)
    gap_m = 3.4 - params.safety_min_distance_m
    assert v[0] <= params.safety_closing_rate_per_s * gap_m + 1e-9
    alone = collision_barrier("follower", np.array([3.9, 0.0]), np.zeros(2), [peer], params)
    assert alone[0] >= 3.0  # without the leader the follower does flee the peer


def test_boxed_in_between_the_leader_and_a_peer_a_follower_closes_on_neither() -> None:
    """The leader 2.0 m west (inside the 3 m minimum: move east), a peer 1.0 m east closing at 3 m/s. Fleeing the
    peer runs into the leader and leaving the leader's minimum runs into the peer: the follower holds."""
    params = ControlParams(mode="improved", safety_min_distance_m=3.0)
    leader = NeighbourInfo(33, "leader", np.array([-2.0, 0.0]), np.zeros(2), 10.0)
    peer = NeighbourInfo(63, "follower", np.array([1.0, 0.0]), np.array([-3.0, 0.0]), 10.0)
    v = collision_barrier("follower", np.array([-1.0, 0.5]), np.zeros(2), [leader, peer], params)
    assert abs(v[0]) <= 1e-9
