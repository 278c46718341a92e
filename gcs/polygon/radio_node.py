"""The ground station as a node of the swarm radio: it hears what reaches its antenna at the launch site.

No rescue team hears every drone losslessly: its ground station sits at the launch site with the same radio as the
drones, so the polygon it sends on depends on which boundary drones are in its range and on what the others relay
(:mod:`vehicle_agents.core.relay`). The node never transmits on the swarm radio (its orders stay on their own
link); it is one more receiver row of the radio, with the id :data:`~comms.radio_model.GROUND_NODE_ID`
(:class:`~gcs.lockstep.radio_link.InMemoryRadio` in lockstep, ``python -m comms.radio --ground-node`` over
processes, which delivers to ``radio/0/inbox``), and files what it hears with the drones' own rule (newest ``seq`` per
origin, relayed copies unpacked and admitted as by the drones). ``radio.gcs_lossless = true`` keeps the station outside the radio, hearing every broadcast.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from comms.messages import NeighbourState
from comms.radio_model import GROUND_NODE_ID
from vehicle_agents.core.neighbours import Inbox, heard_after
from vehicle_agents.core.relay import unpacked
from vehicle_agents.core.relay_admission import admitted

ANTENNA_HEIGHT_M = 2.0
"""Height of the ground station's antenna above the launch site [m] (a mast on a vehicle roof)."""
_TABLE_HOLD_S = 60.0


def antenna_enu_m(pads_en_m: NDArray[np.float64]) -> NDArray[np.float64]:
    """Where the ground station's antenna is [m; mission ENU]: the middle of the launch pads, on its mast."""
    centre = np.asarray(pads_en_m, dtype=float)[:, :2].mean(axis=0)
    return np.array([centre[0], centre[1], ANTENNA_HEIGHT_M])


class GroundNode:
    """The station's table of the newest state per drone, from what the radio delivered to it."""

    def __init__(self, antenna_enu_m: NDArray[np.float64], state_rate_hz: float = 0.0) -> None:
        self.antenna_enu_m = np.asarray(antenna_enu_m, dtype=float)
        self.state_rate_hz = state_rate_hz
        """The drones' state rate, against which relayed copies are admitted (0: every copy filed unchecked)."""
        self.heard: Mapping[int, NeighbourState] = {}
        self.refused_copies = 0
        self._departed: frozenset[int] = frozenset()

    def with_antenna(self, positions_enu_m: NDArray[np.float64]) -> NDArray[np.float64]:
        """The vehicles' positions with the antenna as one more row (the radio's receiver set)."""
        return np.vstack([positions_enu_m, self.antenna_enu_m[None, :]])

    def hear(self, states: Sequence[NeighbourState], t_s: float) -> None:
        """File one delivery (direct states and the copies they relay)."""
        if states:
            filed, refused = admitted(unpacked(states), self.heard, t_s, self.state_rate_hz)
            self.refused_copies += refused
            self.heard, self._departed = heard_after(self.heard, self._departed, Inbox(states=filed),
                                                     GROUND_NODE_ID, t_s, _TABLE_HOLD_S)
