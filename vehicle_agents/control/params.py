"""Control parameters and the roster: part of the mission plan, defined in :mod:`mission_plan.control_params` and
:mod:`mission_plan.roster`; re-exported here for the control laws that read them."""

from __future__ import annotations

from mission_plan.control_params import (
    MODES,
    PAPER_PIXEL_GAINS,
    PDOT_READINGS,
    ControlParams,
    ControlParamsError,
    params_for_mode,
)
from mission_plan.roster import RosterEntry

__all__ = ["MODES", "PAPER_PIXEL_GAINS", "PDOT_READINGS", "ControlParams", "ControlParamsError", "RosterEntry",
           "params_for_mode"]
