"""A drone waiting in OFFBOARD holds its position over its pad instead of holding a zero velocity."""

from __future__ import annotations

import numpy as np
import pytest

from vehicle_agents.control.hover import HOVER_MAX_SPEED_MPS, hover_velocity
from vehicle_agents.control.types import OwnState


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
