"""The inner followers' law, eq 10: ``u_f = −K_f (q_f − target) + ṫarget + Σ_k β(‖q_f − q_k‖) ω``.

Read literally, eq 10 makes the target the boundary drone i = n·j itself, which would put followers on the edge.
SPEC §2 reading: the target is a point on the segment from the leader to the tracked vehicle, at a fraction chosen
per layer so that the layers sit evenly between leader and edge. With L layers released, layer m (1 = outermost)
sits at radius R (L + 1 − m)/(L + 1); layer 1 tracks its boundary drone at fraction L/(L + 1), and layer m > 1
tracks a follower of layer m − 1 (the paper's ``q_{f_m}`` tracks ``q_{f(m−1)}``) at fraction
(L + 1 − m)/(L + 2 − m). The literal paper reading is fraction = 1.

Layer release (paper §III-B.2): with footprint side s, the leader's footprint covers out to about s/2 and the
boundary drones' in from R − s/2; one layer of footprints covers about ``cover_fraction · s`` radially, so
``L = ceil((R − s) / (cover_fraction · s))`` layers are needed (at least 1). Followers of layers beyond L stay in
a compact flock round the leader (a sunflower pattern of targets) until the flood grows enough to need them.
R comes from the leader's gossiped estimate.

ω (eq 10's constant vector) is read like v in eq 6: gain × unit vector from follower k to this follower.
Improved mode drops this β term: with d = 10 m it pushes followers off their layer places whenever layers are
denser than d (large fleets) and, summed over a crowd at launch, saturates every command; the layer targets
already spread the followers, and the short-range push of :mod:`safety` plus the barrier keep them apart.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from mission_plan.control_params import ControlMode
from vehicle_agents.control.beta import separation_velocity
from vehicle_agents.control.memory import ControlMemory
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.safety import safety_velocity
from vehicle_agents.control.types import ROLE_FOLLOWER, ROLE_LEADER, NeighbourInfo, OwnState

_GOLDEN_ANGLE_RAD = math.pi * (3.0 - math.sqrt(5.0))
_FLOCK_SPACING_M = 3.0


def footprint_side_m(altitude_m: float, fov_deg: float) -> float:
    """Side of the square camera footprint, ``2 h tan(fov/2)`` (SPEC §3)."""
    return 2.0 * altitude_m * math.tan(math.radians(fov_deg) / 2.0)


def layers_needed(radius_m: float, footprint_m: float, cover_fraction: float) -> int:
    """How many follower layers the annulus between the leader's and the boundary drones' footprints needs."""
    return max(1, math.ceil((radius_m - footprint_m) / max(cover_fraction * footprint_m, 1e-6)))


def layer_fraction(layer: int, layers: int) -> float:
    """Where on the segment leader → tracked vehicle a layer-``layer`` follower sits when ``layers`` are out."""
    return (layers + 1 - layer) / (layers + 2 - layer)


def flock_offset_en_m(index: int) -> NDArray[np.float64]:
    """A waiting follower's place round the leader: sunflower pattern, about 3 m between places."""
    r = _FLOCK_SPACING_M * math.sqrt(index + 1.0)
    a = index * _GOLDEN_ANGLE_RAD
    return np.array([r * math.cos(a), r * math.sin(a)])


def follower_step(
    memory: ControlMemory, own: OwnState, neighbours: Sequence[NeighbourInfo], params: ControlParams, t_s: float
) -> tuple[NDArray[np.float64], ControlMemory]:
    """One step of eq 10 with layers: (velocity [m/s; E, N, U], new memory)."""
    entry = memory.entry
    q = np.asarray(own.position_en_m, dtype=float)
    leader = next((n for n in neighbours if n.role == ROLE_LEADER), None)
    ref = next((n for n in neighbours if n.vehicle_id == entry.ref_id), None)
    radii = [n.ring_radius_m for n in neighbours if n.ring_radius_m is not None and n.role in (ROLE_LEADER, ROLE_FOLLOWER)]
    radius = (leader.ring_radius_m if leader is not None and leader.ring_radius_m is not None
              else (float(np.mean(radii)) if radii else memory.ring_radius_m))

    followers = params.followers()
    max_layer = max((e.layer for e in followers), default=1)
    side = footprint_side_m(params.nominal_altitude_m, params.fov_deg)
    layers = min(layers_needed(radius, side, params.follower_cover_fraction), max_layer) if radius is not None else 1
    released = entry.layer <= layers

    if leader is not None and ref is not None and released:
        frac = layer_fraction(entry.layer, layers)
        ql, vl = np.asarray(leader.position_en_m, dtype=float), np.asarray(leader.velocity_en_mps, dtype=float)
        target = ql + frac * (np.asarray(ref.position_en_m, dtype=float) - ql)
        target_rate = vl + frac * (np.asarray(ref.velocity_en_mps, dtype=float) - vl)
    elif leader is not None:
        waiting = [e.vehicle_id for e in followers if e.layer > layers]
        index = waiting.index(entry.vehicle_id) if entry.vehicle_id in waiting else 0
        target = np.asarray(leader.position_en_m, dtype=float) + flock_offset_en_m(index)
        target_rate = np.asarray(leader.velocity_en_mps, dtype=float)
    else:
        target, target_rate = q, np.zeros(2)

    velocity = np.asarray(params.k_follower_per_s) * (target - q) + target_rate
    if params.mode == ControlMode.IMPROVED:
        others = np.array([n.position_en_m for n in neighbours], dtype=float).reshape(-1, 2)
        velocity = velocity + safety_velocity(q, others, params.safety_radius_m, params.safety_gain_mps)
    else:
        peers = np.array([n.position_en_m for n in neighbours if n.role == ROLE_FOLLOWER], dtype=float).reshape(-1, 2)
        velocity = velocity + separation_velocity(q, peers, params.separation_distance_m, params.separation_gain_mps)
    speed = float(np.hypot(velocity[0], velocity[1]))
    if speed > params.max_speed_mps:
        velocity *= params.max_speed_mps / speed
    climb = float(np.clip(params.k_altitude_per_s * (params.nominal_altitude_m - own.altitude_m),
                          -params.descent_speed_mps, params.climb_speed_mps))
    return np.array([velocity[0], velocity[1], climb]), replace(memory, last_t_s=t_s, ring_radius_m=radius)
