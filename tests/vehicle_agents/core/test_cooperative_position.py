"""Drones without GPS correct their drifting odometry from the neighbours they sense (pure, no sockets)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from comms.frames import en_to_body_fr
from comms.messages import FLAG_HAS_GPS, NeighbourRanging, NeighbourState
from mission_plan.roles import Role
from vehicle_agents.core.cooperative_position import (
    NO_CORRECTION,
    PositionCorrection,
    correction_step,
    corrects_odometry,
)

DRIFT_FRAC = 0.01
SIGMA_M = 0.1


def _state(sender: int, position_en_m: np.ndarray, t_s: float, flags: int = 0) -> NeighbourState:
    return NeighbourState(sender_id=sender, role=Role.BOUNDARY, seq=1, t_s=t_s,
                          position_en_m=(float(position_en_m[0]), float(position_en_m[1])), altitude_m=10.0,
                          flags=flags)


def _ranging(observer: int, t_s: float, truth: np.ndarray, ids: list[int], yaw_ned_rad: float) -> NeighbourRanging:
    offsets = truth[ids] - truth[observer]
    body = en_to_body_fr(offsets, yaw_ned_rad)
    return NeighbourRanging(vehicle_id=observer, t_s=t_s, neighbour_ids=ids,
                            forward_right_m=[(float(f), float(r)) for f, r in body])


def test_only_drones_on_drifting_odometry_correct() -> None:
    assert corrects_odometry(True, 0.01, has_gps=False)
    assert not corrects_odometry(True, 0.01, has_gps=True)
    assert not corrects_odometry(True, 0.0, has_gps=False)
    assert not corrects_odometry(False, 0.01, has_gps=False)


def test_a_ring_agrees_on_one_frame_and_keeps_only_the_mean_drift() -> None:
    """Eight drones on a 16 m circle, each drifted its own way by 1 % of a different path: after a few seconds of
    exact ranging (heading known), their corrected positions differ from the truth by one common offset, the mean
    of their drifts (which relative readings cannot see), not by their own drifts."""
    rng = np.random.default_rng(4)
    n = 8
    angles = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    truth = 16.0 * np.column_stack((np.cos(angles), np.sin(angles)))
    flown_m = rng.uniform(40.0, 90.0, n)
    directions = rng.uniform(0.0, 2.0 * math.pi, n)
    drift = DRIFT_FRAC * flown_m[:, None] * np.column_stack((np.cos(directions), np.sin(directions)))
    odometry = truth + drift
    yaws = rng.uniform(-math.pi, math.pi, n)
    states = [PositionCorrection(flown_m=float(d), last_odometry_en_m=(float(o[0]), float(o[1])))
              for d, o in zip(flown_m, odometry)]
    for k in range(1, 151):
        t_s = 0.1 * k
        heard = {j: _state(j, states[j].corrected(odometry[j]), t_s - 0.05) for j in range(n)}
        states = [correction_step(states[i], odometry[i], np.zeros(2), float(yaws[i]),
                                  _ranging(i, t_s, truth, [j for j in range(n) if j != i], float(yaws[i])),
                                  {j: m for j, m in heard.items() if j != i}, t_s, DRIFT_FRAC, SIGMA_M)
                  for i in range(n)]
    errors = np.array([s.corrected(o) for s, o in zip(states, odometry)]) - truth
    raw_spread = np.ptp(drift, axis=0).max()
    assert raw_spread > 0.5
    assert np.ptp(errors, axis=0).max() < 0.02
    assert np.allclose(errors.mean(axis=0), drift.mean(axis=0), atol=0.02)
    assert np.hypot(*errors.mean(axis=0)) < np.hypot(drift[:, 0], drift[:, 1]).mean()


def test_gps_neighbours_and_stale_messages_give_no_reading() -> None:
    truth = np.array([[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]])
    odometry = truth[0] + np.array([0.6, 0.0])
    state = PositionCorrection(flown_m=60.0, last_odometry_en_m=(0.6, 0.0), last_ranging_t_s=1.0)
    heard = {1: _state(1, truth[1], 2.0, flags=FLAG_HAS_GPS), 2: _state(2, truth[2], 1.0)}
    after = correction_step(state, odometry, np.zeros(2), 0.0, _ranging(0, 2.0, truth, [1, 2], 0.0), heard, 2.0,
                            DRIFT_FRAC, SIGMA_M)
    assert after.correction_en_m == (0.0, 0.0)
    assert after.last_ranging_t_s == 1.0


def test_one_reading_pulls_towards_the_drift_in_the_body_frame_of_any_heading() -> None:
    truth = np.array([[0.0, 0.0], [12.0, 5.0]])
    drift = np.array([0.5, -0.3])
    for yaw in (0.0, 1.0, -2.5):
        state = PositionCorrection(flown_m=100.0, last_odometry_en_m=tuple(truth[0] + drift), last_ranging_t_s=0.0)
        for k in range(1, 101):
            t_s = 0.1 * k
            state = correction_step(state, truth[0] + drift, np.zeros(2), yaw, _ranging(0, t_s, truth, [1], yaw),
                                    {1: _state(1, truth[1], t_s)}, t_s, DRIFT_FRAC, SIGMA_M)
        expected = drift / (1.0 + (SIGMA_M ** 2 + 0.1 ** 2) / (DRIFT_FRAC * 100.0 + 0.02) ** 2)
        assert np.allclose(state.correction_en_m, expected, atol=0.01)


def test_the_distance_flown_grows_with_the_odometry_and_nothing_else_moves_without_a_ranging() -> None:
    state = NO_CORRECTION
    for east in (0.0, 3.0, 3.0, 7.0):
        state = correction_step(state, np.array([east, 0.0]), np.zeros(2), 0.0, None, {}, 0.0, DRIFT_FRAC, SIGMA_M)
    assert state.flown_m == pytest.approx(7.0)
    assert state.correction_en_m == (0.0, 0.0)
