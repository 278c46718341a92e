"""Improved mode: equal gaps along the ring by consensus with the two ring neighbours.

The paper spaces boundary drones only by the β repulsion of eq 6, which acts within d: on a ring whose ideal gap
exceeds d (circle at 16 m: 12.6 m > 10 m) nothing evens the gaps out. Here each drone moves along its edge
tangent by ``k (g_ahead − g_behind) / 2`` plus the mean tangential velocity of its two neighbours, where the gaps
are the distances to the previous and next drone in the ring order of the mission plan (B's leader, B..., A...,
A's leader, closing back to B's leader once encircled), signed by the side of the tangent they are on: a
neighbour found on the wrong side (order scrambled in a crowd at launch) gives a negative gap, which drives the
pair back into order instead of letting two drones settle side by side. This is a discrete Laplacian: the gaps converge to equal,
whatever d is, and during encircling the drones spread evenly between the two moving leaders.
"""

from __future__ import annotations

from typing import Mapping

import numpy as np
from numpy.typing import NDArray

from vehicle_agents.control.types import NeighbourInfo


def ring_neighbours(
    own_id: int, ring_order: tuple[int, ...], heard: Mapping[int, NeighbourInfo], closed: bool
) -> tuple[NeighbourInfo | None, NeighbourInfo | None]:
    """(previous, next) heard drones in counter-clockwise ring order, skipping ones not heard (lost).

    While the ring is open (not encircled) the chain ends at A's and B's leaders: no wrapping round.
    """
    if own_id not in ring_order:
        return None, None
    i = ring_order.index(own_id)
    n = len(ring_order)

    def walk(step: int) -> NeighbourInfo | None:
        for k in range(1, n):
            j = i + step * k
            if not closed and (j < 0 or j >= n):
                return None
            other = ring_order[j % n]
            if other == own_id:
                return None
            if other in heard:
                return heard[other]
        return None

    return walk(-1), walk(+1)


def spacing_velocity(
    own_en_m: NDArray[np.float64],
    tangent_en: NDArray[np.float64],
    previous: NeighbourInfo,
    following: NeighbourInfo,
    gain_per_s: float,
) -> NDArray[np.float64]:
    """Tangential consensus velocity [m/s; E, N] between the previous and next drone (counter-clockwise)."""
    t = np.asarray(tangent_en, dtype=float)
    q = np.asarray(own_en_m, dtype=float)
    ahead = np.asarray(following.position_en_m, dtype=float) - q
    behind = q - np.asarray(previous.position_en_m, dtype=float)
    gap_ahead = float(np.linalg.norm(ahead)) * (1.0 if float(np.dot(ahead, t)) >= 0.0 else -1.0)
    gap_behind = float(np.linalg.norm(behind)) * (1.0 if float(np.dot(behind, t)) >= 0.0 else -1.0)
    neighbours_speed = 0.5 * float(np.dot(np.asarray(following.velocity_en_mps) + np.asarray(previous.velocity_en_mps), t))
    return (0.5 * gain_per_s * (gap_ahead - gap_behind) + neighbours_speed) * t
