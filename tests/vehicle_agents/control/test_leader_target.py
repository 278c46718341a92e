"""The leader's target (eq 9): the boundary drones' vertex mean, except in improved mode once encircled, where it is
the area centroid of the ring they form. Boundary drones bunched on one side tell the three candidates apart (the
mean, the area centroid, any single drone)."""

from __future__ import annotations

import numpy as np
import pytest

from mission_plan.roles import Role
from vehicle_agents.control.leader import leader_step
from vehicle_agents.control.params import ControlParams, RosterEntry
from vehicle_agents.control.step import initial_memory
from vehicle_agents.control.types import NeighbourInfo, OwnState

# A 10 m square with three more drones bunched on its top edge: area centroid (5, 5), vertex mean (26/7, 50/7).
RING = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0), (1.0, 10.0), (2.0, 10.0), (3.0, 10.0)]
LEADER_AT = np.array([25.0, 5.0])


def direction_to_target(mode: str, encircled: bool) -> np.ndarray:
    roster = tuple(RosterEntry(i + 1, Role.BOUNDARY, "A", i) for i in range(len(RING))) + (
        RosterEntry(99, Role.LEADER, has_gps=True),)
    params = ControlParams(roster=roster, mode=mode, k_leader_per_s=(0.5, 0.5))
    heard = [NeighbourInfo(i + 1, Role.BOUNDARY, np.array(p), np.zeros(2), 10.0, encircled=encircled)
             for i, p in enumerate(RING)]
    velocity, _ = leader_step(initial_memory(Role.LEADER, 99, params), OwnState(LEADER_AT, 10.0, has_gps=True), heard,
                              params, 0.0)
    return velocity[:2] / np.linalg.norm(velocity[:2])


def unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def test_improved_mode_once_encircled_aims_at_the_area_centroid() -> None:
    assert direction_to_target("improved", encircled=True) == pytest.approx(unit(np.array([5.0, 5.0]) - LEADER_AT))


@pytest.mark.parametrize(("mode", "encircled"), [("improved", False), ("paper", True), ("paper", False)])
def test_otherwise_the_leader_aims_at_the_vertex_mean(mode: str, encircled: bool) -> None:
    mean = np.mean(np.array(RING), axis=0)
    assert direction_to_target(mode, encircled) == pytest.approx(unit(mean - LEADER_AT))
