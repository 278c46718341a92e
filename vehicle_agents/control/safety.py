"""Improved mode: collision-aware separation between ALL roles.

The paper separates boundary drones from boundary drones (eq 6) and followers from followers (eq 10) only; a
follower and the leader, or a boundary drone and a follower, never push each other. Here every vehicle heard of
the same or a higher right of way (:data:`RIGHT_OF_WAY`) within ``radius_m`` pushes this one away with
``gain · (1 − x/radius)²`` m/s, strong enough near contact to beat
the tracking terms, zero at the radius. Last comes a barrier filter (:func:`safety_filter`) on the command that
counts on no more braking than PX4 gives and on neighbours' positions carried forward by their message age, so
that radio delay and a fast head-on approach cannot close a gap below the minimum.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.types import ROLE_BOUNDARY, ROLE_FOLLOWER, ROLE_LEADER, NeighbourInfo, SensedOffsets

_PASSES = 3

RIGHT_OF_WAY = {ROLE_BOUNDARY: 0, ROLE_LEADER: 1, ROLE_FOLLOWER: 2}
"""Lower number = right of way. Boundary drones hold the cage, the leader the centre; followers make room."""


def yielded_to(own_role: str, neighbours: Sequence[NeighbourInfo]) -> list[NeighbourInfo]:
    """The neighbours this drone must keep clear of: those of its own or a higher right of way.

    Without this, a crowd of followers round the launch site boxes in the leader and the boundary drones (each
    pushing against everyone, nobody moves); with it, followers step aside and the others fly through.
    """
    mine = RIGHT_OF_WAY.get(own_role, 2)
    return [n for n in neighbours if RIGHT_OF_WAY.get(n.role, 2) <= mine]


def safety_velocity(
    own_en_m: NDArray[np.float64], others_en_m: NDArray[np.float64], radius_m: float, gain_mps: float
) -> NDArray[np.float64]:
    """Sum of short-range pushes [m/s; E, N] away from every other vehicle closer than ``radius_m``."""
    others = np.asarray(others_en_m, dtype=float).reshape(-1, 2)
    if others.shape[0] == 0 or radius_m <= 0.0 or gain_mps == 0.0:
        return np.zeros(2)
    diff = np.asarray(own_en_m, dtype=float)[None, :] - others
    dist = np.hypot(diff[:, 0], diff[:, 1])
    near = (dist < radius_m) & (dist > 1e-9)
    if not np.any(near):
        return np.zeros(2)
    strength = gain_mps * (1.0 - dist[near] / radius_m) ** 2 / dist[near]
    return (strength[:, None] * diff[near]).sum(axis=0)


def stopping_speed_mps(gap_m: float, braking_mps2: float, reaction_s: float) -> float:
    """The fastest approach [m/s] from which a vehicle still stops within ``gap_m``.

    Solves ``v·reaction_s + v²/(2·braking_mps2) = gap_m`` for v: the vehicle keeps closing for the reaction time
    (control period, PX4's velocity response, radio delay) and then brakes at ``braking_mps2``. Zero for no gap.
    """
    if gap_m <= 0.0:
        return 0.0
    if braking_mps2 <= 0.0:
        return gap_m / reaction_s if reaction_s > 0.0 else math.inf
    return braking_mps2 * (math.sqrt(reaction_s * reaction_s + 2.0 * gap_m / braking_mps2) - reaction_s)


def predicted_positions_en_m(neighbours: Sequence[NeighbourInfo], horizon_cap_s: float = 1.0) -> NDArray[np.float64]:
    """Where the neighbours are now [m; E, N]: their last heard position carried forward by their heard velocity over
    the message's age (at most ``horizon_cap_s``). A message 0.2 s old from a drone at 4 m/s is 0.8 m out of date."""
    if not neighbours:
        return np.zeros((0, 2))
    positions = np.array([n.position_en_m for n in neighbours], dtype=float).reshape(-1, 2)
    velocities = np.array([n.velocity_en_mps for n in neighbours], dtype=float).reshape(-1, 2)
    ages = np.array([min(max(n.age_s, 0.0), horizon_cap_s) for n in neighbours])
    return positions + velocities * ages[:, None]


def braking_horizon_m(min_distance_m: float, closing_speed_mps: float, braking_mps2: float, reaction_s: float) -> float:
    """Beyond this distance no neighbour can constrain a drone closing at ``closing_speed_mps`` (so the barrier
    may ignore it): the minimum distance plus the reaction and braking distance at that speed."""
    braking = closing_speed_mps**2 / (2.0 * braking_mps2) if braking_mps2 > 0.0 else math.inf
    return min_distance_m + closing_speed_mps * reaction_s + braking


def safety_filter(
    velocity_en_mps: NDArray[np.float64],
    own_en_m: NDArray[np.float64],
    others_en_m: NDArray[np.float64],
    min_distance_m: float,
    radius_m: float,
    closing_rate_per_s: float,
    others_velocity_en_mps: NDArray[np.float64] | None = None,
    braking_mps2: float = 0.0,
    reaction_s: float = 0.0,
    others_give_way: NDArray[np.bool_] | None = None,
) -> NDArray[np.float64]:
    """Limit the speed towards each close neighbour so that the gap can never close below ``min_distance_m``.

    For a neighbour at distance x < ``radius_m`` in direction u, the component of the command along u is capped at
    ``min(closing_rate_per_s · (x − min_distance_m), stopping_speed_mps(x − min_distance_m)) + v_h · u`` (negative
    inside the minimum: move away), where v_h is the neighbour's last heard velocity: this drone alone keeps the
    closing speed within the barrier, whatever the other does (a peer doing the same only adds margin). The linear
    term is the barrier near the minimum; the stopping term (when ``braking_mps2`` > 0) keeps a fast approach from
    further out within what PX4's acceleration limit can still stop, so the barrier acts before it is too late.
    A control-barrier style filter, applied neighbour by neighbour, nearest last so that it has the final word; with
    several close neighbours the constraints are projected on cyclically (:data:`_PASSES` rounds) so that a later
    correction seldom undoes an earlier one.

    Inside the minimum of several neighbours at once (a crowd at launch, pads closer than the minimum) the demands
    to move away can contradict each other (one neighbour north, one south); the nearest then won and the drone
    could close on the other at full speed. So when any neighbour is inside the minimum, a second round projects
    on the same constraints with "move away" relaxed to "do not close" (``v_h · u``): separating is wished for,
    not closing is kept. In that round a neighbour marked in ``others_give_way`` (it keeps clear of this drone too)
    is not fled from: its approach is its own to stop, and fleeing it inside a crowd runs into the others (``large``,
    lockstep: a follower fled a peer closing from behind at 3 m/s straight into the stationary leader, 0.94 m apart).
    A command that already meets every constraint passes both rounds unchanged.
    """
    v = np.asarray(velocity_en_mps, dtype=float).copy()
    others = np.asarray(others_en_m, dtype=float).reshape(-1, 2)
    if others.shape[0] == 0:
        return v
    diff = others - np.asarray(own_en_m, dtype=float)[None, :]
    dist = np.hypot(diff[:, 0], diff[:, 1])
    # The projections run on plain floats: each is a handful of multiplications on 2-vectors, where numpy's
    # per-call overhead would cost more than the arithmetic (every drone runs this at every control step).
    distance = dist.tolist()
    close = [k for k in np.argsort(-dist).tolist() if 1e-9 < distance[k] < radius_m]
    if not close:
        return v
    east, north = diff[:, 0].tolist(), diff[:, 1].tolist()
    heard_v = None if others_velocity_en_mps is None else np.asarray(others_velocity_en_mps, dtype=float).tolist()
    constraints = []
    relaxed = []
    for k in close:
        x = distance[k]
        ux, uy = east[k] / x, north[k] / x
        gap_m = x - min_distance_m
        allowed = closing_rate_per_s * gap_m
        if braking_mps2 > 0.0 and gap_m > 0.0:
            allowed = min(allowed, stopping_speed_mps(gap_m, braking_mps2, reaction_s))
        own_closing = heard_v[k][0] * ux + heard_v[k][1] * uy if heard_v is not None else 0.0
        constraints.append((ux, uy, allowed + own_closing))
        fled = own_closing if others_give_way is None or not others_give_way[k] else max(own_closing, 0.0)
        relaxed.append((ux, uy, max(allowed, 0.0) + fled))
    passes = _PASSES if len(close) > 1 else 1
    vx, vy = _project(float(v[0]), float(v[1]), constraints, passes)
    if relaxed != constraints:
        vx, vy = _project(vx, vy, relaxed, passes)
    v[0], v[1] = vx, vy
    return v


def _project(vx: float, vy: float, constraints: Sequence[tuple[float, float, float]], passes: int
             ) -> tuple[float, float]:
    """Cyclic projection of (vx, vy) onto the half-planes ``v · (ux, uy) <= allowed``, in the given order."""
    for _ in range(passes):
        for ux, uy, allowed in constraints:
            along = vx * ux + vy * uy
            if along > allowed:
                vx -= (along - allowed) * ux
                vy -= (along - allowed) * uy
    return vx, vy


def sensed_positions_en_m(obstacles: Sequence[NeighbourInfo], own_en_m: NDArray[np.float64],
                          own_velocity_en_mps: NDArray[np.float64], sensed: SensedOffsets) -> NDArray[np.float64]:
    """Where the barrier keeps clear of each obstacle now [m; (K, 2) E, N]: a sensed one at this drone's position
    when measured plus the measured offset, carried forward by its velocity over the measurement's age; the others
    where their messages put them (:func:`predicted_positions_en_m`)."""
    positions = predicted_positions_en_m(obstacles)
    row_of = sensed.row_of()
    rows = [(k, row_of[n.vehicle_id]) for k, n in enumerate(obstacles) if n.vehicle_id in row_of]
    if not rows:
        return positions
    age_s = sensed.age_s
    measured_at_en_m = np.asarray(own_en_m, dtype=float) - np.asarray(own_velocity_en_mps, dtype=float) * age_s
    mine, theirs = (list(side) for side in zip(*rows))
    velocities = np.array([obstacles[k].velocity_en_mps for k in mine], dtype=float).reshape(-1, 2)
    positions[mine] = measured_at_en_m + sensed.offsets_en_m[theirs] + velocities * age_s
    return positions


def collision_barrier(role: str, velocity_en_mps: NDArray[np.float64], own_en_m: NDArray[np.float64],
                      heard: Sequence[NeighbourInfo], params: ControlParams,
                      heard_en_m: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Improved mode's last word on a command [m/s; E, N]: :func:`safety_filter` against every heard vehicle of the
    same or a higher right of way at ``safety_min_distance_m``, after a last-resort barrier at half that distance
    against those who give way to this one; and when both kinds are near, the last resort against everyone once
    more, so that it has the final word.

    Keeping clear of those with the right of way can contradict not running over one who gives way: in a launch
    crowd the leader, told to leave a boundary drone's 2.5 m, drove into a follower it had already closed to
    1.3 m (0.82 m apart under bursty radio loss, seed 2). A gap of half the minimum is a collision to avoid;
    the full minimum is room to keep; so the collision floor wins.

    Boxed in, a follower does not flee other followers: they keep clear of it too, so their approach is theirs to
    stop, while fleeing one inside a crowd runs into another or into the leader, who does not give way to followers
    (:func:`safety_filter`'s ``others_give_way``). Boundary drones still flee each other: the two groups' leading
    drones meet head on, and without it a ``circle`` ring under ``moderate`` weather failed (seed 11, IoU 0.006).

    Neighbours are at ``heard_en_m`` when given (:func:`sensed_positions_en_m`), else where their last message,
    carried forward by its age, puts them; the barrier counts on PX4's
    braking (``safety_braking_mps2`` after ``safety_reaction_s``) and so looks as far out as a drone at twice the
    speed limit (two drones head on) needs to stop.
    """
    obstacles = yielded_to(role, heard)
    ids = {n.vehicle_id for n in obstacles}
    yields = np.array([n.vehicle_id not in ids for n in heard], dtype=bool)
    heard_en_m = predicted_positions_en_m(heard) if heard_en_m is None else heard_en_m
    brake = params.safety_braking_mps2
    reaction = params.safety_reaction_s
    horizon_speed_mps = 2.0 * params.max_speed_mps
    last_resort_m = 0.5 * params.safety_min_distance_m
    last_resort_radius_m = max(params.safety_min_distance_m,
                               braking_horizon_m(last_resort_m, horizon_speed_mps, brake, reaction))
    v = np.asarray(velocity_en_mps, dtype=float)
    if yields.any():
        v = safety_filter(v, own_en_m, heard_en_m[yields], last_resort_m, last_resort_radius_m,
                          params.safety_closing_rate_per_s, braking_mps2=brake, reaction_s=reaction)
    if obstacles:
        others_v = np.array([n.velocity_en_mps for n in obstacles], dtype=float).reshape(-1, 2)
        obstacles_en_m = heard_en_m[~yields]
        radius_m = max(params.safety_radius_m,
                       braking_horizon_m(params.safety_min_distance_m, horizon_speed_mps, brake, reaction))
        follower_rank = RIGHT_OF_WAY[ROLE_FOLLOWER]
        other_followers = (np.array([RIGHT_OF_WAY.get(n.role, 2) == follower_rank for n in obstacles], dtype=bool)
                           if role == ROLE_FOLLOWER else None)
        v = safety_filter(v, own_en_m, obstacles_en_m, params.safety_min_distance_m, radius_m,
                          params.safety_closing_rate_per_s, others_v, braking_mps2=brake, reaction_s=reaction,
                          others_give_way=other_followers)
        if yields.any():
            v = safety_filter(v, own_en_m, heard_en_m, last_resort_m, last_resort_radius_m,
                              params.safety_closing_rate_per_s, braking_mps2=brake, reaction_s=reaction)
    return v
