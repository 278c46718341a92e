"""The small values a control step reads and writes: own state, heard neighbours, the velocity command.

Everything is in the mission ENU frame (metres, seconds). A drone without GPS still knows its position in this
frame: its odometry starts at its pad, whose offset from the launch site is part of the mission plan.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from mission_plan.roles import ROLE_BOUNDARY, ROLE_FOLLOWER, ROLE_LEADER, ROLES

__all__ = ["ROLES", "ROLE_BOUNDARY", "ROLE_FOLLOWER", "ROLE_LEADER", "NeighbourInfo", "OwnState", "SensedOffsets",
           "VelocityCommand"]


@dataclass(frozen=True)
class OwnState:
    """What the drone knows of itself: odometry position [m; mission E, N], altitude [m], velocity [m/s; E, N]."""

    position_en_m: NDArray[np.float64]
    altitude_m: float
    velocity_en_mps: NDArray[np.float64] = field(default_factory=lambda: np.zeros(2))
    has_gps: bool = False


@dataclass(frozen=True)
class NeighbourInfo:
    """One neighbour as last heard over the radio (its own claim, ``age_s`` old when used).

    Role extras: boundary drones send ``group`` ("A"/"B"), ``leading`` (no drone of its group ahead of it), ``encircled`` (they know the ring is closed) and
    ``ring_radius_m`` (their estimate of the flood's radius seen from the leader, gossiped for follower layers).
    """

    vehicle_id: int
    role: str
    position_en_m: NDArray[np.float64]
    velocity_en_mps: NDArray[np.float64]
    altitude_m: float
    age_s: float = 0.0
    group: str | None = None
    leading: bool = False
    encircled: bool = False
    ring_radius_m: float | None = None


@dataclass(frozen=True)
class SensedOffsets:
    """Neighbours' offsets from this drone [m; (K, 2) E, N], row k that of ``neighbour_ids[k]``, as its
    relative-position sensor measured them ``age_s`` ago (:mod:`vehicle_agents.core.sensed_neighbours`)."""

    neighbour_ids: tuple[int, ...]
    offsets_en_m: NDArray[np.float64]
    age_s: float = 0.0

    def row_of(self) -> Mapping[int, int]:
        """Each sensed neighbour's row."""
        return {vid: k for k, vid in enumerate(self.neighbour_ids)}


@dataclass(frozen=True)
class VelocityCommand:
    """A velocity setpoint [m/s; mission E, N, U] and a yaw [rad; NED, 0 = north] for the autopilot."""

    velocity_enu_mps: NDArray[np.float64]
    yaw_ned_rad: float = 0.0

    @property
    def velocity_en_mps(self) -> NDArray[np.float64]:
        """The horizontal part [m/s; E, N]."""
        return self.velocity_enu_mps[:2]
