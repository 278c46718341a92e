"""Improved mode: where a boundary drone flies while its camera shows no edge, kept within reach of the last edge.

Algorithm 1 (paper, line 8; SPEC §2) only climbs while the image holds one class; eq 8's ``u_c`` and, in the
improved mode, the ring spacing keep pushing the drone along the last tangent it saw. On a straight line that
tangent leaves a curved flood: a leading drone at 3 m/s is 30 m out after 10 s, beyond what any climb brings back
into view, and the ring opens (on turbid water beside brown soil a thin strip of water at the image border is
easily missed, so a drone just outside the edge loses it this way). So once the edge is out of view (a one-class frame, or no usable frame for longer than :data:`HOLD_S`), the
drone stops moving along the ring and searches around the last edge it trusted:

* along that edge's tangent it returns to the point where it last saw the edge (its ring neighbours keep their
  gaps to it there);
* across it, it moves at :data:`SEARCH_SPEED_MPS` towards the side the frame says the edge lies (only land:
  towards the water side of the last normal; only water: towards the land side), so it swings over the edge where
  the camera misses it; it turns back at a reach from the line that grows from half a footprint at the nominal
  altitude by :data:`REACH_GROWTH_MPS` per second lost, never beyond :data:`MAX_REACH_FOOTPRINTS` footprints, and
  then heads back over the line before it listens to the frames again (frames that lie cannot hold it at the
  bound); without frames it sweeps from bound to bound.

Algorithm 1's climb goes on meanwhile (footprint grows), so the sweep and the wider view meet the edge again.

A drone whose camera has shown only land or only water since take-off (a thin strip of turbid water at the
image's border is easily missed) has no edge of its own yet; the plan gives it one (:func:`launch_edge`): SPEC §4
puts the boundary drones in a column along the edge tangent through the launch point, the leader and the followers
in columns behind them, away from the flood. So its pad lies on that line and the water is on the far side of the
boundary column from the others' pads. Otherwise it would only climb in place, up to the ceiling if the camera
never finds the water there.
Pure: positions are the drone's own estimate, in the mission frame of its odometry, like the anchor.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from mission_plan.roles import ROLE_BOUNDARY
from mission_plan.roster import RosterEntry

HOLD_S = 1.0
"""Without any usable frame, the drone holds its track (keeps its ring motion) this long after the last edge [s]:
the doubtful-frame hold of :mod:`vehicle_agents.perception.edge_trust`."""
SEARCH_SPEED_MPS = 1.0
"""Speed of the sweep across the last edge line, and the fastest return along it [m/s]."""
RETURN_GAIN_PER_S = 0.5
"""Along the last tangent the drone returns to where it saw the edge at this rate (capped at the sweep speed)."""
REACH_GROWTH_MPS = 0.5
"""The sweep's reach from the edge line grows by this much per second lost [m/s] ..."""
MAX_REACH_FOOTPRINTS = 2.0
"""... up to this many footprint sides at the nominal altitude."""

TOWARDS_LAND = 1.0
TOWARDS_WATER = -1.0
_TURNED_AT_BOUND = 2.0
"""A remembered sweep direction of this magnitude: turned back at the reach, heading for the line (module doc)."""


@dataclass(frozen=True)
class LastEdge:
    """The last edge a boundary drone acted on: a point of it [m; mission E, N], its unit normal (water to land),
    its unit tangent (water on the left), and when [s]."""

    point_en_m: NDArray[np.float64]
    normal_en: NDArray[np.float64]
    tangent_en: NDArray[np.float64]
    t_s: float


def launch_edge(roster: Sequence[RosterEntry], vehicle_id: int, t_s: float) -> LastEdge | None:
    """The edge the plan implies for ``vehicle_id`` (module doc): through its pad, the normal from the boundary
    drones' pads towards the other vehicles' pads; None when the roster lacks the pads to say."""
    own = next((e.pad_en_m for e in roster if e.vehicle_id == vehicle_id), None)
    boundary = [e.pad_en_m for e in roster if e.role == ROLE_BOUNDARY and e.pad_en_m is not None]
    behind = [e.pad_en_m for e in roster if e.role != ROLE_BOUNDARY and e.pad_en_m is not None]
    if own is None or not boundary or not behind:
        return None
    away = np.mean(np.asarray(behind, dtype=float), axis=0) - np.mean(np.asarray(boundary, dtype=float), axis=0)
    length = float(np.hypot(away[0], away[1]))
    if not length > 1e-6:
        return None
    normal = away / length
    return LastEdge(np.asarray(own, dtype=float), normal, np.array([-normal[1], normal[0]]), t_s)


def is_searching(last_edge: LastEdge, one_class_frame: bool, t_s: float) -> bool:
    """With no edge in view, is the search due? On a frame of one class at once; without a usable frame, once the
    last edge is more than :data:`HOLD_S` old (until then the drone holds its track)."""
    return one_class_frame or t_s - last_edge.t_s > HOLD_S


def reach_m(lost_s: float, footprint_side_m: float) -> float:
    """How far from the last edge line the sweep goes [m] after ``lost_s`` without the edge."""
    start = 0.5 * footprint_side_m
    return min(start + REACH_GROWTH_MPS * max(lost_s, 0.0), MAX_REACH_FOOTPRINTS * footprint_side_m)


def first_sweep_sign(only_land: bool, only_water: bool, across_m: float) -> float:
    """Where the sweep starts: towards the water side over land, the land side over water, else towards the line."""
    if only_land:
        return TOWARDS_WATER
    if only_water:
        return TOWARDS_LAND
    return TOWARDS_WATER if across_m > 0.0 else TOWARDS_LAND


def search_velocity(
    own_en_m: NDArray[np.float64],
    last_edge: LastEdge,
    sweep_sign: float,
    only_land: bool,
    only_water: bool,
    t_s: float,
    footprint_side_m: float,
) -> tuple[NDArray[np.float64], float]:
    """(horizontal velocity [m/s; E, N], the sweep direction to remember) of a drone searching for the edge.

    ``sweep_sign`` is what the previous step returned: 0 when the search starts, else the direction (+1 towards
    the land side of the last edge, -1 towards the water side), doubled while heading back from the bound. The
    sweep turns back when it reaches :func:`reach_m` from the line, so the drone never leaves the band of width
    2 x reach around it.
    """
    offset = np.asarray(own_en_m, dtype=float) - last_edge.point_en_m
    across = float(offset @ last_edge.normal_en)
    along = float(offset @ last_edge.tangent_en)
    direction = float(np.sign(sweep_sign)) if sweep_sign != 0.0 else first_sweep_sign(only_land, only_water, across)
    returning = abs(sweep_sign) == _TURNED_AT_BOUND and direction * across < 0.0
    if not returning and (only_land or only_water):
        direction = TOWARDS_WATER if only_land else TOWARDS_LAND
    reach = reach_m(t_s - last_edge.t_s, footprint_side_m)
    if direction * across >= reach:
        direction, returning = -direction, True
    along_mps = float(np.clip(-RETURN_GAIN_PER_S * along, -SEARCH_SPEED_MPS, SEARCH_SPEED_MPS))
    velocity = direction * SEARCH_SPEED_MPS * last_edge.normal_en + along_mps * last_edge.tangent_en
    return velocity, direction * (_TURNED_AT_BOUND if returning else 1.0)
