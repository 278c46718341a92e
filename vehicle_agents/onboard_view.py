"""Pure conversions between what the agent's links carry and what the control law reads (and back).

The control law (``vehicle_agents.control``) lives in the mission ENU frame; the autopilot speaks local NED from the
vehicle's pad; the radio carries ``NeighbourState`` messages. These functions are the only translation between
them, and every frame change goes through ``comms.frames``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from comms.frames import swap_ned_enu
from comms.messages import (
    FLAG_AIRBORNE,
    FLAG_ARMED,
    FLAG_CLIMBING_TO_FIND_EDGE,
    FLAG_HAS_GPS,
    FLAG_LEADING,
    FLAG_LEAVING,
    FLAG_LOW_BATTERY,
    FLAG_OFFBOARD,
    FLAG_SEES_EDGE,
    MAX_EDGE_POINTS,
    HeardState,
    NeighbourState,
)
from comms.px4_mode_names import MAVSDK_OFFBOARD
from mission_plan.roles import Role
from vehicle_agents.autopilot_link import AutopilotTelemetry
from vehicle_agents.control.types import NeighbourInfo, OwnState, VelocityCommand
from vehicle_agents.perception.result import PerceptionResult

EDGE_POINTS_PER_MESSAGE = 24
"""Edge points a boundary drone sends per state message (evenly subsampled): enough for the polygon, small on air."""


def own_state(tel: AutopilotTelemetry, pad_enu_m: Sequence[float], has_gps: bool) -> OwnState:
    """The drone's own state in the mission frame from its autopilot's local NED odometry and its pad offset."""
    east_m, north_m, up_m = swap_ned_enu(*tel.position_ned_m)
    east_mps, north_mps, _ = swap_ned_enu(*tel.velocity_ned_mps)
    return OwnState(
        position_en_m=np.array([pad_enu_m[0] + east_m, pad_enu_m[1] + north_m]),
        altitude_m=up_m,
        velocity_en_mps=np.array([east_mps, north_mps]),
        has_gps=has_gps,
    )


def neighbour_info(msg: HeardState, age_s: float) -> NeighbourInfo:
    """One neighbour's message as the control law reads it, ``age_s`` old (what only the wire carries, such as the
    ring radius in ``extras``, comes through here in both engines)."""
    return neighbour_info_at(msg, np.array(msg.position_en_m, dtype=float), np.array(msg.velocity_en_mps, dtype=float),
                             age_s)


def neighbour_info_at(msg: HeardState, position_en_m: NDArray[np.float64], velocity_en_mps: NDArray[np.float64],
                      age_s: float) -> NeighbourInfo:
    """One neighbour's message as the control law reads it, with the position [m; E, N] and velocity [m/s; E, N]
    given (the neighbour filter's estimate instead of the message's own)."""
    ring_radius_m = msg.extras.get("ring_radius_m")
    return NeighbourInfo(
        vehicle_id=msg.sender_id,
        role=msg.role,
        position_en_m=position_en_m,
        velocity_en_mps=velocity_en_mps,
        altitude_m=msg.altitude_m,
        age_s=age_s,
        group=msg.group or None,
        leading=msg.has(FLAG_LEADING),
        encircled=msg.encircle_complete,
        ring_radius_m=None if ring_radius_m is None else float(ring_radius_m),
    )


def velocity_ned(command: VelocityCommand) -> tuple[float, float, float]:
    """The control law's ENU velocity as the NED setpoint PX4 flies (non-finite components become 0)."""
    v = command.velocity_enu_mps
    ned = swap_ned_enu(v[0], v[1], v[2])
    return tuple(c if math.isfinite(c) else 0.0 for c in ned)  # type: ignore[return-value]


def edge_points_for_radio(edge_points_en_m: NDArray[np.float64]) -> list[tuple[float, float]]:
    """Absolute edge points [m; mission E, N] evenly subsampled to :data:`EDGE_POINTS_PER_MESSAGE` for the radio."""
    points = np.asarray(edge_points_en_m, dtype=float).reshape(-1, 2)
    if not math.isfinite(float(points.sum())):
        points = points[np.all(np.isfinite(points), axis=1)]
    if len(points) > EDGE_POINTS_PER_MESSAGE:
        points = points[_even_subsample(len(points))]
    return list(map(tuple, points[:MAX_EDGE_POINTS].tolist()))


@lru_cache(maxsize=512)
def _even_subsample(count: int) -> NDArray[np.intp]:
    """Indices of :data:`EDGE_POINTS_PER_MESSAGE` points spread evenly over ``count`` (the same few counts recur)."""
    indices = np.linspace(0, count - 1, EDGE_POINTS_PER_MESSAGE).round().astype(int)
    indices.setflags(write=False)
    return indices


def state_message(
    *,
    seq: int,
    t_s: float,
    broadcast: NeighbourInfo,
    own: OwnState,
    tel: AutopilotTelemetry,
    perception: PerceptionResult | None,
    edge_points_en_m: NDArray[np.float64],
    leaving: bool,
    low_battery: bool,
) -> NeighbourState:
    """This drone's broadcast: the control law's own message (``own_broadcast``: role, group, leading, encircled,
    ring radius) plus status flags, GPS where fitted, and for boundary drones the edge points it sees (absolute)."""
    flags = 0
    flags |= FLAG_ARMED if tel.armed else 0
    flags |= FLAG_AIRBORNE if tel.in_air else 0
    flags |= FLAG_OFFBOARD if tel.flight_mode == MAVSDK_OFFBOARD else 0
    flags |= FLAG_HAS_GPS if own.has_gps else 0
    flags |= FLAG_LEAVING if leaving else 0
    flags |= FLAG_LOW_BATTERY if low_battery else 0
    if perception is not None:
        flags |= FLAG_SEES_EDGE if perception.has_edge else 0
        flags |= FLAG_CLIMBING_TO_FIND_EDGE if (perception.only_land or perception.only_water) else 0
    flags |= FLAG_LEADING if broadcast.leading else 0
    gps_ok = own.has_gps and tel.has_global_position and math.isfinite(tel.latitude_deg)
    extras = {} if broadcast.ring_radius_m is None else {"ring_radius_m": float(broadcast.ring_radius_m)}
    return NeighbourState(
        sender_id=broadcast.vehicle_id,
        role=broadcast.role,  # type: ignore[arg-type]
        seq=seq,
        t_s=float(t_s),
        position_en_m=(float(own.position_en_m[0]), float(own.position_en_m[1])),
        altitude_m=float(own.altitude_m),
        velocity_en_mps=(float(own.velocity_en_mps[0]), float(own.velocity_en_mps[1])),
        velocity_up_mps=float(-tel.velocity_ned_mps[2]),
        yaw_ned_rad=float(tel.yaw_ned_rad),
        lat_deg=float(tel.latitude_deg) if gps_ok else None,
        lon_deg=float(tel.longitude_deg) if gps_ok else None,
        flags=flags,
        battery_fraction=float(tel.battery_fraction),
        group=(broadcast.group or ""),  # type: ignore[arg-type]
        encircle_complete=broadcast.encircled,
        edge_points_en_m=edge_points_for_radio(edge_points_en_m) if broadcast.role == Role.BOUNDARY else [],
        extras={k: v for k, v in extras.items() if math.isfinite(v)},
    )
