"""A drone waiting in OFFBOARD holds its position over its pad instead of holding a zero velocity."""

from __future__ import annotations

import numpy as np
import pytest

from vehicle_agents.control.hover import HOVER_MAX_SPEED_MPS, hover_velocity
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.step import hover_step
from vehicle_agents.control.types import NeighbourInfo, OwnState, SensedOffsets


def test_over_its_pad_at_altitude_it_asks_for_nothing() -> None:
    own = OwnState(position_en_m=np.array([14.0, 1.5]), altitude_m=10.0)
    assert np.allclose(hover_velocity(own, (14.0, 1.5), 10.0).velocity_enu_mps, 0.0)


def test_blown_off_it_is_pulled_back_and_no_faster_than_the_limit() -> None:
    near = OwnState(position_en_m=np.array([14.4, 1.5]), altitude_m=9.8)
    assert hover_velocity(near, (14.0, 1.5), 10.0).velocity_enu_mps == pytest.approx([-0.4, 0.0, 0.2])
    far = OwnState(position_en_m=np.array([20.0, -6.0]), altitude_m=10.0)
    velocity = hover_velocity(far, (14.0, 1.5), 10.0).velocity_enu_mps
    assert np.linalg.norm(velocity) == pytest.approx(HOVER_MAX_SPEED_MPS)
    assert velocity[0] < 0.0 < velocity[1]


def test_improved_mode_hovers_through_the_collision_barrier() -> None:
    """A leader whose GPS estimate puts it 1 m east of its pad pulls west towards a follower it senses 1.2 m west:
    improved mode's barrier turns the pull into moving away; paper mode has no barrier."""
    own = OwnState(np.array([1.0, 0.0]), 10.0)
    follower = NeighbourInfo(11, "follower", np.array([-1.5, 0.0]), np.zeros(2), 10.0, age_s=0.05)
    sensed = SensedOffsets((11,), np.array([[-1.2, 0.0]]), age_s=0.05)
    improved = ControlParams(mode="improved", sensed_barrier=True, ranging_available=True)
    kept = hover_step("leader", 9, own, (0.0, 0.0), 10.0, [follower], improved, sensed)
    plain = hover_step("leader", 9, own, (0.0, 0.0), 10.0, [follower], ControlParams(mode="paper"), sensed)
    assert plain.velocity_en_mps[0] < -0.5
    assert kept.velocity_en_mps[0] >= 0.0
