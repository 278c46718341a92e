"""What the ground station publishes for anyone drawing the mission: vehicle status, events, operator requests.

These are the public messages behind the live map (``python -m gcs.dashboard``) and any other client:

* ``floodwatch/<mission>/gcs/vehicles`` — :class:`VehicleStatusReport`, every vehicle's status, several times a
  second: what QGroundControl's fleet view holds (flight mode, armed, battery, GCS link, failsafe) beside what
  only the swarm knows (role, the agent's liveliness, its position estimate and camera footprint);
* ``floodwatch/<mission>/gcs/events`` — :class:`MissionEvent`, one per event-log line and per alert;
* ``floodwatch/<mission>/gcs/operator`` — :class:`OperatorRequest`, hold / resume / land-all asked by an operator
  (the ground station decides, logs it, and turns it into its own ``MissionCommand``);
* ``floodwatch/<mission>/sim/flood_edge`` — :class:`FloodEdgeTruth`, the TRUE flood edge (simulation only).

Positions are WGS84 (``lat_deg``/``lon_deg``, GeoJSON order ``[lon, lat]`` in lists) so a client needs no mission
frame; ages are seconds at ``wall_s`` (UTC epoch seconds of publication), so a client adds its own delay.
"""

from __future__ import annotations

import enum
import math

import msgspec

LonLat = tuple[float, float]


class LinkState(str, enum.Enum):
    """The GCS MAVLink link to one vehicle: heartbeats arriving, late (over half the loss bound), or lost."""

    OK = "ok"
    STALE = "stale"
    LOST = "lost"


class EventKind(str, enum.Enum):
    """What a :class:`MissionEvent` reports; all but ``INFO`` and ``OPERATOR`` are alerts for the rescue centre."""

    INFO = "info"
    VEHICLE_LOST = "vehicle_lost"
    AGENT_LOST = "agent_lost"
    FAILSAFE = "failsafe"
    RING_GAP = "ring_gap"
    UNCOVERED_EDGE = "uncovered_edge"
    OPERATOR = "operator"


ALERT_KINDS = frozenset({EventKind.VEHICLE_LOST, EventKind.AGENT_LOST, EventKind.FAILSAFE, EventKind.RING_GAP,
                         EventKind.UNCOVERED_EDGE})


class OperatorCommand(str, enum.Enum):
    """Orders an operator may give the whole fleet from the map (with the dashboard's token)."""

    HOLD = "hold"
    RESUME = "resume"
    LAND = "land"


class VehicleStatus(msgspec.Struct, frozen=True, omit_defaults=True):
    """One vehicle as the ground station sees it. ``None`` = not known yet (no heartbeat, no state message).

    ``heartbeat_age_s``: since the last MAVLink heartbeat on the GCS link; ``state_age_s``: since the agent's
    newest state message (position, velocity); both at the report's ``wall_s``. ``footprint_lonlat``: the camera's
    ground footprint (a square of side 2·h·tan(fov/2) under a downward camera), corners counter-clockwise.
    """

    vehicle_id: int
    role: str
    link: LinkState
    agent_alive: bool
    group: str = ""
    flight_mode: str = ""
    armed: bool = False
    failsafe: bool = False
    battery_fraction: float | None = None
    lat_deg: float | None = None
    lon_deg: float | None = None
    altitude_m: float | None = None
    velocity_en_mps: tuple[float, float] = (0.0, 0.0)
    footprint_lonlat: list[LonLat] = []
    heartbeat_age_s: float | None = None
    state_age_s: float | None = None


class VehicleStatusReport(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/vehicles/1"):
    """Every vehicle's status at mission time ``t_s`` (``flood_t_s`` None before the flood clock starts)."""

    t_s: float
    wall_s: float
    phase: str
    vehicles: list[VehicleStatus]
    flood_t_s: float | None = None
    home_lat_deg: float | None = None
    home_lon_deg: float | None = None
    operator_order: str = ""
    """The operator's standing order (``hold`` or ``land``), empty while the mission runs on its own."""

    def __post_init__(self) -> None:
        if not (math.isfinite(self.t_s) and math.isfinite(self.wall_s)):
            raise ValueError("non-finite report time")


class MissionEvent(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/event/1"):
    """One line of the ground station's event log, or an alert. ``active`` False clears an earlier alert of the
    same ``kind`` and ``vehicle_id`` (a gap that closed, an edge seen again)."""

    seq: int
    t_s: float
    wall_s: float
    kind: EventKind
    text: str
    vehicle_id: int | None = None
    active: bool = True


class OperatorRequest(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/operator/1"):
    """An operator's order from a dashboard that checked the operator's token; ``origin`` names who asked."""

    seq: int
    wall_s: float
    command: OperatorCommand
    origin: str = ""


class FloodEdgeTruth(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/floodedge/1"):
    """The simulated flood's TRUE edge at flood time ``flood_t_s`` (never exists in a real deployment)."""

    flood_t_s: float
    ring_lonlat: list[LonLat]
