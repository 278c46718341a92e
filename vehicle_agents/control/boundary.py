"""The boundary drone's law, eq 8 = eq 4 with eqs 5 and 6: ``u_b = K_b (p − q) + ṗ + Σ_h β(‖q − q_h‖) v + u_c``,
wrapped in Algorithm 1 (climb while only land or only water is in view).

Paper mode: every drone of a group flies u_c until it knows the ring is closed; spacing comes from β alone
(among boundary drones heard, eq 6). Improved mode: only each group's leading drone flies u_c (at a faster
speed); the others keep equal gaps to their ring neighbours (:mod:`ring_spacing`), and a short-range push from
every heard boundary drone (:mod:`safety`: followers and the leader give way) replaces β; with the edge out of
view it leaves the ring's motion and searches around the last edge it saw (:mod:`edge_search`).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from mission_plan.control_params import ControlMode
from mission_plan.geometry import footprint_side_m
from mission_plan.roster import RosterEntry
from vehicle_agents.control.beta import separation_velocity
from vehicle_agents.control.edge_rate import feedforward, update_edge_rate
from vehicle_agents.control.edge_search import LastEdge, is_searching, launch_edge, search_velocity
from vehicle_agents.control.encircle import (
    encircle_velocity,
    heard_encircled,
    is_leading,
    meets_other_leader,
    travel_sign,
)
from vehicle_agents.control.memory import ControlMemory
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.ring_spacing import ring_neighbours, spacing_velocity
from vehicle_agents.control.safety import safety_velocity, yielded_to
from vehicle_agents.control.types import ROLE_BOUNDARY, NeighbourInfo, OwnState
from vehicle_agents.control.vision_tracking import altitude_rate_mps, tracked_offset_en_m, tracking_velocity
from vehicle_agents.perception.edge_continuity import continuous_edge_points
from vehicle_agents.perception.result import PerceptionResult


def _positions(neighbours: Sequence[NeighbourInfo]) -> NDArray[np.float64]:
    if not neighbours:
        return np.zeros((0, 2))
    return np.array([n.position_en_m for n in neighbours], dtype=float).reshape(-1, 2)


def boundary_step(
    memory: ControlMemory,
    own: OwnState,
    perception: PerceptionResult | None,
    neighbours: Sequence[NeighbourInfo],
    params: ControlParams,
    t_s: float,
) -> tuple[NDArray[np.float64], ControlMemory]:
    """One step of eq 8 + Algorithm 1: (velocity [m/s; E, N, U], new memory)."""
    entry = memory.entry
    q = np.asarray(own.position_en_m, dtype=float)
    dt = 0.0 if memory.last_t_s is None else max(t_s - memory.last_t_s, 0.0)
    boundary_nbrs = [n for n in neighbours if n.role == ROLE_BOUNDARY]

    offset = tracked_offset_en_m(perception, params.edge_point_tracking) if perception is not None else None
    tangent, normal = memory.tangent_en, memory.normal_en
    edge_points = memory.edge_points_en_m
    if offset is not None and perception is not None and perception.edge_tangent_en is not None:
        tangent = np.asarray(perception.edge_tangent_en, dtype=float)
        normal = np.asarray(perception.edge_normal_en, dtype=float)
        reported = perception.edge_points_en_m if perception.shore_points_en_m is None else perception.shore_points_en_m
        edge_points = q[None, :] + continuous_edge_points(reported, tangent, normal, perception.footprint_side_m)
    edge_rate = update_edge_rate(memory.edge_rate, None if offset is None else q + offset, t_s, params.pdot_filter_time_s)

    leading = is_leading(entry, boundary_nbrs, params)
    sign = travel_sign(entry.group)
    travelled = memory.travelled_m
    if tangent is not None:
        travelled += max(float(np.dot(own.velocity_en_mps, sign * tangent)), 0.0) * dt
    encircled = memory.encircled or heard_encircled(boundary_nbrs)
    if not encircled and leading and tangent is not None:
        encircled = meets_other_leader(entry, q, sign * tangent, boundary_nbrs, travelled, params)
    encircled_t_s = memory.encircled_t_s if memory.encircled else (t_s if encircled else None)

    last_edge = memory.last_edge
    if offset is not None and tangent is not None and normal is not None:
        last_edge = LastEdge(q + offset, normal, tangent, t_s)
    one_class = perception is not None and (perception.only_land or perception.only_water)
    if last_edge is None and one_class and params.mode == ControlMode.IMPROVED:
        last_edge = launch_edge(params.roster, entry.vehicle_id, t_s)
    sweep_sign = 0.0
    if (offset is None and params.mode == ControlMode.IMPROVED and last_edge is not None
            and is_searching(last_edge, one_class, t_s)):
        velocity, sweep_sign = search_velocity(
            q, last_edge, memory.sweep_sign, perception is not None and perception.only_land,
            perception is not None and perception.only_water, t_s,
            float(footprint_side_m(params.nominal_altitude_m, params.fov_deg)))
        velocity += safety_velocity(q, _positions(yielded_to(ROLE_BOUNDARY, neighbours)), params.safety_radius_m,
                                    params.safety_gain_mps)
    else:
        velocity = _edge_velocity(offset, edge_rate.rate_en_mps, normal, params)
        _add_ring_velocity(velocity, q, entry, tangent, neighbours, leading, encircled, params)
    speed = float(np.hypot(velocity[0], velocity[1]))
    if speed > params.max_speed_mps:
        velocity *= params.max_speed_mps / speed
    climb_mps, climbing = altitude_rate_mps(
        perception, own.altitude_m, params.nominal_altitude_m, params.climb_speed_mps, params.descent_speed_mps,
        params.k_altitude_per_s, params.max_altitude_m,
    )
    new_memory = replace(
        memory,
        last_t_s=t_s,
        edge_rate=edge_rate,
        tangent_en=tangent,
        normal_en=normal,
        climbing=climbing,
        climb_events=memory.climb_events + (1 if climbing and not memory.climbing else 0),
        leading=leading,
        encircled=encircled,
        encircled_t_s=encircled_t_s,
        travelled_m=travelled,
        edge_points_en_m=edge_points,
        last_edge=last_edge,
        sweep_sign=sweep_sign,
    )
    return np.array([velocity[0], velocity[1], climb_mps]), new_memory


def _edge_velocity(offset: NDArray[np.float64] | None, edge_rate_en_mps: NDArray[np.float64] | None,
                   normal: NDArray[np.float64] | None, params: ControlParams) -> NDArray[np.float64]:
    """Eq 5 towards the edge seen, with the ṗ feed-forward (zero without an edge in view)."""
    velocity = np.zeros(2)
    if offset is not None:
        ff = feedforward(edge_rate_en_mps, normal, params.pdot_reading)
        velocity += tracking_velocity(offset, params.k_boundary_per_s, ff)
    return velocity


def _add_ring_velocity(velocity: NDArray[np.float64], q: NDArray[np.float64], entry: RosterEntry,
                       tangent: NDArray[np.float64] | None, neighbours: Sequence[NeighbourInfo], leading: bool,
                       encircled: bool, params: ControlParams) -> None:
    """Add, in place, the motion along the edge: encircling (eq 6) until the leading drones meet, then the ring's
    spacing; improved mode keeps equal gaps to the ring neighbours and a braking-aware barrier, the paper mode eq 7's
    β separation."""
    sign = travel_sign(entry.group)
    boundary_nbrs = [n for n in neighbours if n.role == ROLE_BOUNDARY]
    if params.mode != ControlMode.IMPROVED:
        velocity += separation_velocity(q, _positions(boundary_nbrs), params.separation_distance_m,
                                        params.separation_gain_mps)
        if not encircled and tangent is not None:
            velocity += encircle_velocity(entry.group, tangent, params.encircle_speed_mps)
        return
    velocity += safety_velocity(q, _positions(yielded_to(ROLE_BOUNDARY, neighbours)), params.safety_radius_m,
                                params.safety_gain_mps)
    heard = {n.vehicle_id: n for n in boundary_nbrs}
    previous, following = ring_neighbours(entry.vehicle_id, params.ring_order(), heard, encircled)
    ahead = following if sign > 0 else previous
    if tangent is not None:
        if previous is not None and following is not None and not (leading and not encircled):
            velocity += spacing_velocity(q, tangent, previous, following, params.spacing_gain_per_s)
        elif not encircled and (leading or ahead is None):
            velocity += encircle_velocity(entry.group, tangent, params.encircle_speed_mps)
