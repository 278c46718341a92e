"""What a drone's control law remembers between steps (a frozen value, replaced every step)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from vehicle_agents.control.edge_rate import EdgeRateState
from vehicle_agents.control.edge_search import LastEdge
from vehicle_agents.control.params import RosterEntry


@dataclass(frozen=True)
class ControlMemory:
    """Per-drone state of the laws.

    ``tangent_en``/``normal_en``: the last edge direction seen (used while Algorithm 1 climbs); ``travelled_m``:
    distance flown along the edge in the group's direction (odometry); ``encircled``/``encircled_t_s``: the ring is
    known to be closed, and since when; ``ring_radius_m``: the flood radius estimate gossiped for follower layers.
    """

    role: str
    vehicle_id: int
    entry: RosterEntry
    last_t_s: float | None = None
    edge_rate: EdgeRateState = field(default_factory=EdgeRateState)
    tangent_en: NDArray[np.float64] | None = None
    normal_en: NDArray[np.float64] | None = None
    climbing: bool = False
    climb_events: int = 0
    leading: bool = False
    encircled: bool = False
    encircled_t_s: float | None = None
    travelled_m: float = 0.0
    ring_radius_m: float | None = None
    edge_points_en_m: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)))
    """The last edge points seen, absolute [m; E, N]: what a boundary drone reports to the ground station."""
    last_edge: LastEdge | None = None
    """Improved mode: the last edge acted on, the anchor of the search while the edge is out of view."""
    sweep_sign: float = 0.0
    """Improved mode, searching: the sweep's direction across the last edge (+1 towards land), 0 when not searching."""
