"""The one entry point of the control laws, called by the lockstep engine and by the per-process agent alike.

Inputs are only what one drone can know: its own odometry in the mission frame (:class:`OwnState`), its camera's
perception result, and the neighbours it heard over the radio (:class:`NeighbourInfo`, with their age). The
output is a velocity setpoint in mission ENU and the drone's new control memory. Pure: no clock, no I/O.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from mission_plan.control_params import ControlMode
from vehicle_agents.control.boundary import boundary_step
from vehicle_agents.control.hover import hover_velocity
from vehicle_agents.control.follower import follower_step
from vehicle_agents.control.launch_stand_ins import launch_stand_ins
from vehicle_agents.control.leader import leader_step
from vehicle_agents.control.memory import ControlMemory
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.safety import collision_barrier, sensed_positions_en_m
from vehicle_agents.control.types import (
    ROLE_BOUNDARY,
    ROLE_FOLLOWER,
    ROLE_LEADER,
    ROLES,
    NeighbourInfo,
    OwnState,
    SensedOffsets,
    VelocityCommand,
)
from vehicle_agents.perception.result import PerceptionResult


def initial_memory(role: str, vehicle_id: int, params: ControlParams) -> ControlMemory:
    """The memory a drone starts its mission with (its roster entry looked up in ``params``)."""
    if role not in ROLES:
        raise ValueError(f"role: must be one of {', '.join(ROLES)}, got {role!r}")
    entry = params.entry(vehicle_id)
    if entry.role != role:
        entry = replace(entry, vehicle_id=vehicle_id, role=role)
    return ControlMemory(role=role, vehicle_id=vehicle_id, entry=entry)


def usable_neighbours(own_id: int, neighbours: Sequence[NeighbourInfo], timeout_s: float) -> list[NeighbourInfo]:
    """Neighbours other than oneself, heard within ``timeout_s``, with finite positions and velocities."""
    return [
        n for n in neighbours
        if n.vehicle_id != own_id and n.age_s <= timeout_s
        and math.isfinite(n.position_en_m[0] + n.position_en_m[1] + n.velocity_en_mps[0] + n.velocity_en_mps[1])
    ]


def control_step(
    role: str,
    memory: ControlMemory,
    own: OwnState,
    perception: PerceptionResult | None,
    neighbours: Sequence[NeighbourInfo],
    params: ControlParams,
    t_s: float,
    sensed: SensedOffsets | None = None,
) -> tuple[VelocityCommand, ControlMemory]:
    """One control step of ``role``: boundary (eq 8, Algorithm 1), leader (eq 9) or follower (eq 10).

    The yaw is held at north (0 rad NED) so that camera footprints stay axis-aligned squares. Improved mode
    passes the command through the collision barrier of :func:`safety.safety_filter` against every heard vehicle
    it must keep clear of (same or higher right of way), after a short last-resort barrier against the others;
    at launch the plan's pads stand in for the vehicles not heard yet (:mod:`launch_stand_ins`). With ``sensed``
    (and ``params.sensed_barrier``) the barrier places the neighbours its relative-position sensor measured where
    it measured them (:func:`safety.sensed_positions_en_m`).
    """
    heard = usable_neighbours(memory.vehicle_id, neighbours, params.neighbour_timeout_s)
    if role == ROLE_BOUNDARY:
        velocity, memory = boundary_step(memory, own, perception, heard, params, t_s)
    elif role == ROLE_LEADER:
        velocity, memory = leader_step(memory, own, heard, params, t_s)
    elif role == ROLE_FOLLOWER:
        velocity, memory = follower_step(memory, own, heard, params, t_s)
    else:
        raise ValueError(f"role: must be one of {', '.join(ROLES)}, got {role!r}")
    if params.mode == ControlMode.IMPROVED:
        velocity[:2] = _kept_clear(role, memory.vehicle_id, velocity[:2], own, heard, neighbours, params, t_s, sensed)
    if not np.all(np.isfinite(velocity)):
        velocity = np.zeros(3)
    return VelocityCommand(velocity_enu_mps=velocity, yaw_ned_rad=0.0), memory


def hover_step(role: str, vehicle_id: int, own: OwnState, pad_en_m: Sequence[float], altitude_m: float,
               neighbours: Sequence[NeighbourInfo], params: ControlParams,
               sensed: SensedOffsets | None = None) -> VelocityCommand:
    """The hold over the pad of a drone waiting to start (:func:`vehicle_agents.control.hover.hover_velocity`),
    through improved mode's collision barrier like every other command: the drone holds its pad where its own
    estimate puts it, and a GPS fix's bias moves that point by a metre towards a neighbour 1.5 m away (``circle``
    under ``moderate`` as processes: leader and follower 0.93 m apart before the mission started)."""
    velocity = np.array(hover_velocity(own, pad_en_m, altitude_m).velocity_enu_mps, dtype=float)
    if params.mode == ControlMode.IMPROVED:
        heard = usable_neighbours(vehicle_id, neighbours, params.neighbour_timeout_s)
        velocity[:2] = _kept_clear(role, vehicle_id, velocity[:2], own, heard, neighbours, params, 0.0, sensed)
    if not np.all(np.isfinite(velocity)):
        velocity = np.zeros(3)
    return VelocityCommand(velocity_enu_mps=velocity, yaw_ned_rad=0.0)


def _kept_clear(role: str, vehicle_id: int, velocity_en_mps: NDArray[np.float64], own: OwnState,
                heard: list[NeighbourInfo], neighbours: Sequence[NeighbourInfo], params: ControlParams,
                elapsed_s: float, sensed: SensedOffsets | None) -> NDArray[np.float64]:
    """The horizontal command through the collision barrier against the heard neighbours and, at launch, the pads
    of those not heard yet; the neighbours the sensor measured where it measured them."""
    stand_ins = launch_stand_ins(params, vehicle_id, neighbours, elapsed_s)
    obstacles = heard + stand_ins if stand_ins else heard
    if not obstacles:
        return velocity_en_mps
    positions = (sensed_positions_en_m(obstacles, own.position_en_m, own.velocity_en_mps, sensed)
                 if sensed is not None and params.sensed_barrier else None)
    return collision_barrier(role, velocity_en_mps, own.position_en_m, obstacles, params, positions)


def own_broadcast(memory: ControlMemory, own: OwnState, t_s: float) -> NeighbourInfo:
    """What this drone tells its neighbours this step (age 0 at the sender; receivers add the delay)."""
    entry = memory.entry
    return NeighbourInfo(
        vehicle_id=memory.vehicle_id,
        role=memory.role,
        position_en_m=np.asarray(own.position_en_m, dtype=float),
        velocity_en_mps=np.asarray(own.velocity_en_mps, dtype=float),
        altitude_m=float(own.altitude_m),
        age_s=0.0,
        group=entry.group,
        leading=memory.leading,
        encircled=memory.encircled,
        ring_radius_m=memory.ring_radius_m,
    )
