"""The operator's standing order: hold until resumed; land is final."""

from __future__ import annotations

from comms.gcs_status import OperatorCommand as C
from gcs.dashboard.operator_orders import command_for, next_order


def test_hold_stands_until_resume_and_land_is_final() -> None:
    order = next_order(None, C.HOLD)
    assert order is C.HOLD and command_for("start", order) == "hold"
    order = next_order(order, C.RESUME)
    assert order is None and command_for("start", order) == "start"
    order = next_order(next_order(None, C.LAND), C.RESUME)
    assert order is C.LAND
    assert next_order(order, C.HOLD) is C.LAND
    assert command_for("phase", order) == "land"
