"""The roster: who flies which role, known to every drone before take-off (part of the mission plan)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class RosterEntry:
    """One vehicle of the mission plan.

    ``group`` is "A" (keeps water on its left, counter-clockwise) or "B" for boundary drones; ``rank`` is the order
    of departure inside the group (0 leads). Followers have ``layer`` (1 = outermost) and ``ref_id``: the vehicle
    they track, a boundary drone for layer 1 (eq 10, i = n j) or a follower of the layer outside (paper §III-B.2).
    ``pad_en_m`` is where it stands at launch [m; mission E, N]: until a drone is first heard over the radio, its pad
    is all the others know of where it is (:mod:`vehicle_agents.control.launch_stand_ins`).
    """

    vehicle_id: int
    role: str
    group: str | None = None
    rank: int = 0
    layer: int = 0
    ref_id: int | None = None
    has_gps: bool = False
    pad_en_m: tuple[float, float] | None = None
