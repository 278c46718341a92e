"""Failsafe action tables: every parameter value in range has an action."""

from comms.px4 import Px4Mode
from mock_autopilot.px4_failsafes import DATALINK_LOSS_ACTIONS, DISARM, OFFBOARD_LOSS_ACTIONS, TERMINATE, battery_action
from mock_autopilot.px4_params import PARAM_SPECS


def test_tables_cover_the_parameter_ranges() -> None:
    obl = PARAM_SPECS["COM_OBL_RC_ACT"]
    assert set(OFFBOARD_LOSS_ACTIONS) == set(range(int(obl.min_value), int(obl.max_value) + 1))
    dll = PARAM_SPECS["NAV_DLL_ACT"]
    assert set(DATALINK_LOSS_ACTIONS) == set(range(int(dll.min_value), int(dll.max_value) + 1))
    assert OFFBOARD_LOSS_ACTIONS[6] == TERMINATE and OFFBOARD_LOSS_ACTIONS[7] == DISARM
    assert DATALINK_LOSS_ACTIONS[0] is None and DATALINK_LOSS_ACTIONS[2] is Px4Mode.AUTO_RTL


def test_battery_action() -> None:
    assert battery_action(1, 3) is None
    assert battery_action(3, 0) is None
    assert battery_action(2, 1) is Px4Mode.AUTO_RTL
    assert battery_action(2, 2) is Px4Mode.AUTO_LAND
    assert battery_action(2, 3) is Px4Mode.AUTO_RTL
    assert battery_action(3, 3) is Px4Mode.AUTO_LAND
    assert battery_action(3, 1) is Px4Mode.AUTO_LAND
