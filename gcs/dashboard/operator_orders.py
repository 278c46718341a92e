"""The operator's standing order over the fleet (pure): hold and land stand until resumed.

The ground station repeats its ``MissionCommand`` every half second (newest wins at the agents), so an operator's
hold must replace what it repeats, not be sent once: :func:`command_for` is what to repeat in each phase.
"""

from __future__ import annotations

from comms.gcs_status import OperatorCommand


def next_order(current: OperatorCommand | None, request: OperatorCommand) -> OperatorCommand | None:
    """The standing order after ``request``: RESUME clears it; a LAND is never undone by a HOLD (the fleet is
    coming down); otherwise the newest request stands."""
    if request is OperatorCommand.RESUME:
        return None if current is not OperatorCommand.LAND else current
    if current is OperatorCommand.LAND:
        return current
    return request


def command_for(default: str, order: OperatorCommand | None) -> str:
    """The ``MissionCommand.command`` to repeat: the standing order if there is one, else the phase's own."""
    return default if order is None else order.value
