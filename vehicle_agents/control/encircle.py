"""The encircling velocity u_c of eq 4 and how a drone knows, from radio messages only, that encircling is over.

Group A keeps the water on its left (moves along the image's edge tangent, counter-clockwise), group B on its right.
u_c stops "when the encircling of the flood zone completes" (paper §III-A); SPEC §2 reads that as the moment the
two groups' leading drones meet on the far side. Our rule, using only what a drone hears:

* a boundary drone is *leading* when it hears no drone of its own group with a lower departure rank (so the next
  one takes over if the leader is lost);
* a leading drone declares the ring closed when it hears the other group's leading drone (one that says so in
  its ``leading`` flag, or the lowest-ranked drone of that group it hears, so the rule holds even where the radio
  message carries no flag) within
  ``meet_distance_m``, AHEAD of it in its direction of travel (at the launch site the other leader is behind),
  after flying at least ``min_encircle_travel_m`` along the edge;
* every boundary drone that hears a neighbour saying ``encircled`` says so too: the news travels round the ring
  hop by hop.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from vehicle_agents.control.params import ControlParams, RosterEntry
from vehicle_agents.control.types import ROLE_BOUNDARY, NeighbourInfo


def travel_sign(group: str | None) -> float:
    """+1 for group A (along the counter-clockwise tangent), −1 for group B."""
    return -1.0 if group == "B" else 1.0


def encircle_velocity(group: str | None, tangent_en: NDArray[np.float64], speed_mps: float) -> NDArray[np.float64]:
    """u_c of eq 4 [m/s; E, N]: the encircling speed along this group's direction of the edge tangent."""
    return travel_sign(group) * speed_mps * np.asarray(tangent_en, dtype=float)


def is_leading(entry: RosterEntry, neighbours: Sequence[NeighbourInfo], params: ControlParams) -> bool:
    """No heard drone of my group has a lower rank (roster ranks: 0 leaves first)."""
    ranks = params.rank_of
    for n in neighbours:
        if n.role == ROLE_BOUNDARY and n.group == entry.group and ranks.get(n.vehicle_id, 1 << 30) < entry.rank:
            return False
    return True


def meets_other_leader(
    entry: RosterEntry,
    own_en_m: NDArray[np.float64],
    travel_dir_en: NDArray[np.float64],
    neighbours: Sequence[NeighbourInfo],
    travelled_m: float,
    params: ControlParams,
) -> bool:
    """A leading drone hears the other group's leading drone close ahead, far from the launch site."""
    if travelled_m < params.min_encircle_travel_m:
        return False
    others = [n for n in neighbours if n.role == ROLE_BOUNDARY and n.group is not None and n.group != entry.group]
    if not others:
        return False
    ranks = params.rank_of
    lowest = min(ranks.get(n.vehicle_id, 1 << 30) for n in others)
    for n in others:
        if not (n.leading or ranks.get(n.vehicle_id, 1 << 30) == lowest):
            continue
        rel = np.asarray(n.position_en_m, dtype=float) - own_en_m
        if float(np.hypot(rel[0], rel[1])) <= params.meet_distance_m and float(np.dot(rel, travel_dir_en)) > 0.0:
            return True
    return False


def heard_encircled(neighbours: Sequence[NeighbourInfo]) -> bool:
    """Some boundary neighbour already knows the ring is closed."""
    return any(n.role == ROLE_BOUNDARY and n.encircled for n in neighbours)
