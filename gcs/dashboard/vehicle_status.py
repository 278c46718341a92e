"""One vehicle's public status from what the ground station holds (pure: no sockets, no clocks)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from comms.frames import GeodeticHome, enu_to_geodetic
from comms.gcs_status import LinkState, VehicleStatus
from comms.messages import FLAG_FAILSAFE, NeighbourState

STALE_FRACTION = 0.5
"""A heartbeat older than this fraction of the loss bound shows the link as stale before it is declared lost."""


@dataclass(frozen=True)
class LinkView:
    """What the GCS MAVLink link says about one vehicle (``math.nan`` / ``math.inf`` when unknown)."""

    flight_mode: str = ""
    armed: bool = False
    battery_fraction: float = math.nan
    heartbeat_age_s: float = math.inf
    failsafe: bool = False


def link_state(heartbeat_age_s: float, lost_after_s: float) -> LinkState:
    """OK, STALE past :data:`STALE_FRACTION` of the loss bound, LOST past it (or never heard)."""
    if not heartbeat_age_s <= lost_after_s:
        return LinkState.LOST
    return LinkState.STALE if heartbeat_age_s > STALE_FRACTION * lost_after_s else LinkState.OK


def footprint_en_m(centre_en_m: tuple[float, float], altitude_m: float, fov_deg: float) -> np.ndarray:
    """The downward camera's ground square (4, 2) [m; E, N], counter-clockwise, side 2·h·tan(fov/2) (the footprint
    the coverage metric uses, axis-aligned as there)."""
    half = max(altitude_m, 0.0) * math.tan(math.radians(fov_deg) / 2.0)
    e, n = centre_en_m
    return np.array([[e - half, n - half], [e + half, n - half], [e + half, n + half], [e - half, n + half]])


def _finite_or_none(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None


def vehicle_status(
    vehicle_id: int,
    role: str,
    group: str,
    link: LinkView,
    state: NeighbourState | None,
    *,
    agent_alive: bool,
    lost_after_s: float,
    state_age_s: float,
    offset_en_m: tuple[float, float],
    home: GeodeticHome,
    fov_deg: float,
) -> VehicleStatus:
    """The status row of one vehicle. Position and velocity come from the agent's newest state message (its own
    estimate, georeferenced by ``offset_en_m`` as the caged polygon is), flight mode, battery and the link from
    the GCS MAVLink link; a failsafe is either the autopilot's announcement or the agent's flag."""
    battery = link.battery_fraction
    if not math.isfinite(battery) and state is not None and state.battery_fraction is not None:
        battery = state.battery_fraction
    common = dict(
        vehicle_id=vehicle_id, role=role, group=group,
        link=link_state(link.heartbeat_age_s, lost_after_s), agent_alive=agent_alive,
        flight_mode=link.flight_mode, armed=link.armed, battery_fraction=_finite_or_none(battery),
        heartbeat_age_s=_finite_or_none(link.heartbeat_age_s),
        failsafe=link.failsafe or bool(state is not None and state.has(FLAG_FAILSAFE)),
    )
    if state is None:
        return VehicleStatus(**common)  # type: ignore[arg-type]
    centre = (state.position_en_m[0] + offset_en_m[0], state.position_en_m[1] + offset_en_m[1])
    lat, lon, _ = enu_to_geodetic(np.array(centre), home)
    corners = enu_to_geodetic(footprint_en_m(centre, state.altitude_m, fov_deg), home)
    return VehicleStatus(
        **common,  # type: ignore[arg-type]
        lat_deg=float(lat), lon_deg=float(lon), altitude_m=float(state.altitude_m),
        velocity_en_mps=(float(state.velocity_en_mps[0]), float(state.velocity_en_mps[1])),
        footprint_lonlat=[(float(c[1]), float(c[0])) for c in corners],
        state_age_s=_finite_or_none(state_age_s),
    )
