"""At launch the plan's pads stand in for neighbours not heard yet (improved mode's collision barrier only).

A drone's first messages can be lost (a radio burst at take-off, a neighbour that starts its mission a little later),
and the collision barrier (:func:`vehicle_agents.control.safety.safety_filter`) only keeps clear of vehicles it has
heard: two drones on pads a little over a metre apart could close below the minimum in the first second before
either hears the other. Every drone knows the roster before take-off, pads included, so a vehicle of the roster
that has not been heard is taken to hover on its pad until it is heard, for as long as the neighbour table would
keep a silent neighbour after a message sent at the start (``neighbour_timeout_s``). The stand-ins feed the barrier
only: the ring, leader and follower laws (eq 6-10) act on what was heard, never on the plan.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.types import NeighbourInfo


def launch_stand_ins(params: ControlParams, own_id: int, heard: Sequence[NeighbourInfo], elapsed_s: float
                     ) -> list[NeighbourInfo]:
    """The roster's vehicles other than ``own_id`` and those ``heard``, each hovering on its pad (age ``elapsed_s``,
    at rest), while ``elapsed_s`` since the mission started is within ``neighbour_timeout_s`` (after that, every
    step returns at once: nothing is built on the control loop)."""
    if elapsed_s > params.neighbour_timeout_s:
        return []
    heard_ids = {n.vehicle_id for n in heard}
    return [
        NeighbourInfo(vehicle_id=entry.vehicle_id, role=entry.role, position_en_m=np.array(entry.pad_en_m, dtype=float),
                      velocity_en_mps=np.zeros(2), altitude_m=params.nominal_altitude_m, age_s=max(0.0, elapsed_s),
                      group=entry.group)
        for entry in params.roster
        if entry.pad_en_m is not None and entry.vehicle_id != own_id and entry.vehicle_id not in heard_ids
    ]
