"""The inner leader's law, eq 9: ``u_l = −K_l (q_l − (1/N) Σ q_b) + (1/N) Σ q̇_b``.

The leader (it has GPS) tracks the centre of mass of the boundary drones it hears. Paper mode uses the vertex
mean exactly as eq 9 writes it. Improved mode, once the ring is closed, tracks the area centroid of the polygon
through the boundary drones (ordered by angle round their mean): the vertex mean is pulled towards wherever the
drones bunch, the area centroid is not. The leader also estimates the flood radius (mean distance from its
target to the boundary drones) and gossips it for the followers' layer release.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from mission_plan.control_params import ControlMode
from mission_plan.geometry import ring_area_centroid
from vehicle_agents.control.memory import ControlMemory
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.safety import safety_velocity, yielded_to
from vehicle_agents.control.types import ROLE_BOUNDARY, ROLE_LEADER, NeighbourInfo, OwnState


def polygon_area_centroid(points_en_m: NDArray[np.float64]) -> NDArray[np.float64]:
    """Area centroid of the polygon through the points ordered by angle round their mean (mean if degenerate)."""
    p = np.asarray(points_en_m, dtype=float).reshape(-1, 2)
    mean = p.mean(axis=0)
    if p.shape[0] < 3:
        return mean
    order = np.argsort(np.arctan2(p[:, 1] - mean[1], p[:, 0] - mean[0]))
    area_m2, centroid = ring_area_centroid(p[order])
    return mean if abs(area_m2) < 5e-10 else centroid


def leader_step(
    memory: ControlMemory, own: OwnState, neighbours: Sequence[NeighbourInfo], params: ControlParams, t_s: float
) -> tuple[NDArray[np.float64], ControlMemory]:
    """One step of eq 9: (velocity [m/s; E, N, U], new memory). No boundary drone heard: hover."""
    q = np.asarray(own.position_en_m, dtype=float)
    boundary = [n for n in neighbours if n.role == ROLE_BOUNDARY]
    velocity = np.zeros(2)
    radius = memory.ring_radius_m
    encircled = memory.encircled or any(n.encircled for n in boundary)
    if boundary:
        qb = np.array([n.position_en_m for n in boundary], dtype=float)
        vb = np.array([n.velocity_en_mps for n in boundary], dtype=float)
        target = polygon_area_centroid(qb) if params.mode == ControlMode.IMPROVED and encircled else qb.mean(axis=0)
        velocity = np.asarray(params.k_leader_per_s) * (target - q) + vb.mean(axis=0)
        radius = float(np.mean(np.hypot(qb[:, 0] - target[0], qb[:, 1] - target[1])))
    if params.mode == ControlMode.IMPROVED:
        others = np.array([n.position_en_m for n in yielded_to(ROLE_LEADER, neighbours)], dtype=float).reshape(-1, 2)
        velocity = velocity + safety_velocity(q, others, params.safety_radius_m, params.safety_gain_mps)
    speed = float(np.hypot(velocity[0], velocity[1]))
    if speed > params.max_speed_mps:
        velocity *= params.max_speed_mps / speed
    climb = float(np.clip(params.k_altitude_per_s * (params.nominal_altitude_m - own.altitude_m),
                          -params.descent_speed_mps, params.climb_speed_mps))
    return np.array([velocity[0], velocity[1], climb]), replace(
        memory, last_t_s=t_s, ring_radius_m=radius, encircled=encircled
    )
