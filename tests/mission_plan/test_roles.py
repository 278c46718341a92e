"""Roles are an enum that fails loudly, and a vehicle the roster does not hold is an error."""

from __future__ import annotations

import pytest

from mission_plan.control_params import ControlParams
from mission_plan.roles import ROLES, Role


def test_role_is_its_wire_name_and_parses_only_known_names() -> None:
    assert Role.parse("leader") is Role.LEADER
    assert Role.BOUNDARY == "boundary" and f"{Role.FOLLOWER}" == "follower"
    assert ROLES == (Role.BOUNDARY, Role.LEADER, Role.FOLLOWER)
    with pytest.raises(ValueError, match="unknown role 'pilot'.*boundary, leader, follower"):
        Role.parse("pilot")


def test_unknown_vehicle_id_is_an_error_not_a_default_boundary_drone() -> None:
    params = ControlParams()
    with pytest.raises(KeyError, match="vehicle 99 is not in the roster"):
        params.entry(99)


def test_control_mode_is_an_enum_equal_to_its_plan_name() -> None:
    from mission_plan.control_params import MODES, ControlMode, params_for_mode

    assert MODES == (ControlMode.PAPER, ControlMode.IMPROVED) and ControlMode("improved") is ControlMode.IMPROVED
    assert params_for_mode("improved", {}, ()).mode == ControlMode.IMPROVED
    with pytest.raises(ValueError):
        ControlMode("fast")
