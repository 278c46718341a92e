"""Versioned, compact message schemas for everything that travels over Zenoh (never over MAVLink).

Wire formats:

* every message except the flood polygon is a MessagePack map (msgspec ``Struct``), self-describing so that any
  Zenoh client in any language can read the public keys; the ``schema`` field names the type and its version
  (``"fw/state/1"``) and is checked on decode;
* the flood polygon is a GeoJSON Feature (:mod:`comms.flood_polygon`) encoded as UTF-8 JSON, so the rescue centre
  can use it without our code; its version is ``properties.schema``.

The paced clock's messages live in :mod:`comms.pace_messages`, the polygon in :mod:`comms.flood_polygon`, the
links' own reports (radio bundles and statistics, peers, dropped forgeries) in :mod:`comms.link_messages`, the checks
every schema shares in :mod:`comms.message_checks`; this module holds the rest and the one codec for them all, and
names every message type (``from comms.messages import PaceReport`` works for all of them).

``decode`` never raises: bad input (malformed, truncated, oversized, wrong version, non-finite numbers) returns
None and is counted in a ``DecodeStats`` (by kind and reason), as SPEC §7 asks for every socket.

Units and frames are in the field names: ``*_en_m`` is mission ENU east/north [m], ``*_enu_m`` east/north/up [m],
``yaw_ned_rad`` is PX4 yaw (0 = north, clockwise). Conversions go through ``comms.frames``.
"""

from __future__ import annotations

import math
import threading
from collections import Counter
from typing import Annotated, Any, Literal, TypeVar, Union

import msgspec
import numpy as np

from comms.flood_polygon import FloodPolygon, FloodPolygonProperties, GeoJsonPolygon  # noqa: F401 (named here too)
from comms.flood_polygon import flood_polygon_from_enu  # noqa: F401 (named here too)
from comms.gcs_status import FloodEdgeTruth, MissionEvent, OperatorRequest, VehicleStatusReport
from comms.link_messages import PeerEvent, RadioBundle, RadioGroupBundle, RadioLinkStats, SecurityEvent
from comms.message_checks import InvalidMessage, Point2, Point3, finite, finite_points
from comms.pace_messages import CameraStats, PaceAck, PaceReport, ParticipantPace, SimClockTick  # noqa: F401
from mission_plan.roles import Role

Group = Literal["A", "B", ""]

MAX_EDGE_POINTS = 256
MAX_RELAYED = 64

# Status flags carried in NeighbourState.flags (a bit field keeps the message small and extensible).
FLAG_ARMED = 1 << 0
FLAG_AIRBORNE = 1 << 1
FLAG_OFFBOARD = 1 << 2
FLAG_HAS_GPS = 1 << 3
FLAG_SEES_EDGE = 1 << 4  # both land and water in the camera image (Algorithm 1 satisfied)
FLAG_CLIMBING_TO_FIND_EDGE = 1 << 5  # Algorithm 1: only land or only water in view, climbing
FLAG_LEADING = 1 << 6  # the leading drone of its boundary group (the one that meets the other group)
FLAG_FAILSAFE = 1 << 7
FLAG_LEAVING = 1 << 8  # the agent is leaving the swarm (vehicle lost, landing): neighbours should drop it
FLAG_LOW_BATTERY = 1 << 9


class NeighbourState(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/state/1"):
    """What a drone broadcasts to its neighbours (and, on the public key, to anyone), typically at 20 Hz.

    ``t_s`` is the sender's mission clock at the time of the estimate (source time); ``seq`` increases by one per
    message so that receivers keep only the newest one when jitter reorders them. ``position_en_m`` is the
    sender's own estimate in the mission frame (odometry for drones without GPS); ``lat_deg``/``lon_deg`` only when
    it has a GPS fix. Boundary-drone extras (paper §III-A, Algorithm 1): ``group`` (A keeps water on its left,
    B on its right), ``encircle_complete`` (the two groups' leading drones met), and ``edge_points_en_m``: points
    of the water edge its camera sees, absolute mission ENU [m], for the ground station's caged polygon.
    ``extras`` carries control-mode specific numbers (e.g. an improved mode's spacing consensus) by name.
    ``relayed``: other drones' states this one heard, passed on for drones out of their range (multi-hop
    knowledge); each copy keeps its origin's ``sender_id``, ``seq`` and ``t_s`` and counts its ``hops`` from the
    origin (0: the origin's own message). Copies carry no ``relayed`` list of their own.
    """

    sender_id: int
    role: Role
    seq: int
    t_s: float
    position_en_m: Point2
    altitude_m: float
    velocity_en_mps: Point2 = (0.0, 0.0)
    velocity_up_mps: float = 0.0
    yaw_ned_rad: float = 0.0
    lat_deg: float | None = None
    lon_deg: float | None = None
    flags: int = 0
    battery_fraction: float | None = None
    group: Group = ""
    encircle_complete: bool = False
    edge_points_en_m: Annotated[list[Point2], msgspec.Meta(max_length=MAX_EDGE_POINTS)] = []
    extras: dict[str, float] = {}
    hops: int = 0
    relayed: Annotated[list[NeighbourState], msgspec.Meta(max_length=MAX_RELAYED)] = []

    def __post_init__(self) -> None:
        _check_state(self)
        if self.hops < 0:
            raise InvalidMessage("hops must be >= 0")
        if self.relayed and any(copy.relayed or copy.hops < 1 for copy in self.relayed):
            raise InvalidMessage("a relayed copy carries hops >= 1 and no relayed list")
        for optional in (self.lat_deg, self.lon_deg, self.battery_fraction):
            if optional is not None and not math.isfinite(optional):
                raise InvalidMessage("non-finite optional field (send None instead)")
        if self.edge_points_en_m and not finite_points(self.edge_points_en_m):
            raise InvalidMessage("non-finite edge point")

    def has(self, flag: int) -> bool:
        return bool(self.flags & flag)


class NeighbourStateForControl(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/state/1"):
    """The part of a :class:`NeighbourState` a drone's control laws and neighbour table read, decoded from the same
    bytes: what an agent needs of every neighbour it hears, ~10 per control tick.

    The edge points (the ground station's polygon), GPS fix and battery are skipped, not parsed: they are most of a
    boundary drone's message and most of the time decoding it. The fields kept get the same checks as in
    :class:`NeighbourState`, so a message either type rejects for them is rejected by both.
    """

    sender_id: int
    role: Role
    seq: int
    t_s: float
    position_en_m: Point2
    altitude_m: float
    velocity_en_mps: Point2 = (0.0, 0.0)
    velocity_up_mps: float = 0.0
    yaw_ned_rad: float = 0.0
    flags: int = 0
    group: Group = ""
    encircle_complete: bool = False
    extras: dict[str, float] = {}

    def __post_init__(self) -> None:
        _check_state(self)

    def has(self, flag: int) -> bool:
        return bool(self.flags & flag)


def _check_state(msg: NeighbourState | NeighbourStateForControl) -> None:
    """The checks both decodings of a state message make on the fields they share; raises InvalidMessage."""
    if msg.sender_id < 0 or msg.seq < 0:
        raise InvalidMessage("sender_id and seq must be >= 0")
    # one sum instead of eight checks: NaN and inf propagate (and a sum overflowing to inf is absurd anyway)
    p, v = msg.position_en_m, msg.velocity_en_mps
    if not math.isfinite(msg.t_s + p[0] + p[1] + msg.altitude_m + v[0] + v[1] + msg.velocity_up_mps + msg.yaw_ned_rad):
        raise InvalidMessage("non-finite state")
    if msg.extras and not math.isfinite(sum(msg.extras.values())):
        raise InvalidMessage("non-finite extra")


HeardState = Union[NeighbourState, NeighbourStateForControl]
"""A neighbour's state as a receiver decoded it: whole (ground station, lockstep radio) or the control part (agent)."""


class CameraFrame(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/camera/1"):
    """One downward camera image as a companion computer would receive it (SPEC §3), with its pose metadata.

    ``image`` is the encoded image (``encoding`` png/jpeg, or raw_bgr: height*width*3 uint8 bytes row-major).
    The pose is what the vehicle knows at capture time: altitude above ground [m], yaw (NED) and the field of
    view, which is all perception needs to turn pixels into metres (paper eq 5).
    """

    vehicle_id: int
    seq: int
    t_s: float
    altitude_m: float
    yaw_ned_rad: float
    fov_deg: float
    width_px: int
    height_px: int
    encoding: Literal["png", "jpeg", "raw_bgr"]
    image: bytes

    def __post_init__(self) -> None:
        if not finite(self.t_s, self.altitude_m, self.yaw_ned_rad, self.fov_deg):
            raise InvalidMessage("non-finite pose")
        if not (0 < self.width_px <= 8192 and 0 < self.height_px <= 8192):
            raise InvalidMessage("bad image size")
        if self.encoding == "raw_bgr" and len(self.image) != self.width_px * self.height_px * 3:
            raise InvalidMessage("raw_bgr size mismatch")


class NeighbourRanging(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/ranging/1"):
    """What one drone's relative-position sensor measured at ``t_s`` (the paper's drones "sense the relative
    positions of their neighbours within limited distances", §I): each neighbour in range, as (forward, right) [m] in
    the drone's horizontal body frame (UWB ranging with angle of arrival, or a camera that sees the others). The
    drone turns them into the mission frame with its own heading estimate, whose error they then carry."""

    vehicle_id: int
    t_s: float
    neighbour_ids: Annotated[list[int], msgspec.Meta(max_length=1024)]
    forward_right_m: Annotated[list[Point2], msgspec.Meta(max_length=1024)]

    def __post_init__(self) -> None:
        if len(self.neighbour_ids) != len(self.forward_right_m):
            raise InvalidMessage("ranging length mismatch")
        if not (math.isfinite(self.t_s) and finite_points(self.forward_right_m)):
            raise InvalidMessage("non-finite ranging")


class BoundaryEdgePoints(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/edge/1"):
    """Water-edge points one boundary drone sees at ``t_s``, absolute mission ENU [m] (for the caged polygon)."""

    sender_id: int
    seq: int
    t_s: float
    points_en_m: Annotated[list[Point2], msgspec.Meta(max_length=4096)]

    def __post_init__(self) -> None:
        if not (math.isfinite(self.t_s) and finite_points(self.points_en_m)):
            raise InvalidMessage("non-finite edge points")


class GroundTruth(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/truth/1"):
    """Every vehicle's TRUE state at simulation time ``t_s`` (from the simulator; feeds the radio and metrics).

    Parallel lists, one entry per vehicle: ids, positions mission ENU [m], velocities ENU [m/s], yaw NED [rad],
    whether the vehicle exists (a crashed/removed vehicle has ``alive`` False and is out of radio range), and the
    body's (roll, pitch) [rad] (the body-fixed camera looks through it; empty: level).
    """

    t_s: float
    vehicle_ids: list[int]
    positions_enu_m: list[Point3]
    velocities_enu_mps: list[Point3] = []
    yaw_ned_rad: list[float] = []
    alive: list[bool] = []
    tilt_rad: list[tuple[float, float]] = []

    def __post_init__(self) -> None:
        n = len(self.vehicle_ids)
        if len(self.positions_enu_m) != n:
            raise InvalidMessage("positions length mismatch")
        for extra in (self.velocities_enu_mps, self.yaw_ned_rad, self.alive, self.tilt_rad):
            if extra and len(extra) != n:
                raise InvalidMessage("truth list length mismatch")
        if not math.isfinite(self.t_s):
            raise InvalidMessage("non-finite t_s")

    def positions_array(self) -> np.ndarray:
        """(N, 3) float array; rows of vehicles that are not alive are NaN (out of everyone's radio range)."""
        p = np.array(self.positions_enu_m, dtype=float).reshape(-1, 3)
        if self.alive:
            p[~np.asarray(self.alive, dtype=bool)] = np.nan
        return p


class MissionCommand(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/command/1"):
    """A ground-station order to the agents: mission phase changes, start, land, hold, resume.

    ``flood_clock_start_t_s``: the mission time at which the flood clock started (SPEC §4: when every vehicle is
    airborne in OFFBOARD), so every agent and the simulator agree on flood time. ``target_ids`` empty = everyone.
    """

    seq: int
    t_s: float
    command: Literal["phase", "start", "hold", "resume", "land", "abort"]
    phase: str = ""
    flood_clock_start_t_s: float | None = None
    target_ids: list[int] = []
    params: dict[str, float] = {}


Message = Union[NeighbourState, CameraFrame, NeighbourRanging, BoundaryEdgePoints, GroundTruth, MissionCommand,
                RadioLinkStats, RadioBundle, RadioGroupBundle, PeerEvent,
                SecurityEvent, SimClockTick, PaceAck, PaceReport, CameraStats, FloodPolygon, VehicleStatusReport,
                MissionEvent, OperatorRequest, FloodEdgeTruth]
M = TypeVar("M", NeighbourState, NeighbourStateForControl, CameraFrame, NeighbourRanging, BoundaryEdgePoints,
            GroundTruth, MissionCommand, RadioLinkStats, RadioBundle, RadioGroupBundle, PeerEvent, SecurityEvent,
            SimClockTick, PaceAck, PaceReport, CameraStats, FloodPolygon, VehicleStatusReport, MissionEvent,
            OperatorRequest, FloodEdgeTruth)

# Largest payload accepted per kind [bytes]: anything larger is dropped before parsing.
MAX_PAYLOAD_BYTES: dict[type, int] = {
    NeighbourState: 16 * 1024,
    NeighbourStateForControl: 16 * 1024,
    CameraFrame: 4 * 1024 * 1024,
    NeighbourRanging: 64 * 1024,
    BoundaryEdgePoints: 256 * 1024,
    GroundTruth: 4 * 1024 * 1024,
    MissionCommand: 16 * 1024,
    RadioLinkStats: 16 * 1024 * 1024,
    RadioBundle: 16 * 1024 * 1024,
    RadioGroupBundle: 16 * 1024 * 1024,
    PeerEvent: 4 * 1024,
    SecurityEvent: 4 * 1024,
    SimClockTick: 1024,
    PaceAck: 1024,
    PaceReport: 1024 * 1024,
    CameraStats: 1024,
    FloodPolygon: 16 * 1024 * 1024,
    VehicleStatusReport: 4 * 1024 * 1024,
    MissionEvent: 16 * 1024,
    OperatorRequest: 1024,
    FloodEdgeTruth: 4 * 1024 * 1024,
}

KINDS: dict[str, type] = {cls.__name__: cls for cls in MAX_PAYLOAD_BYTES}
_JSON_KINDS = frozenset({FloodPolygon})
_SCHEMA_FAMILY = {
    cls: (cls.__struct_config__.tag.rsplit("/", 1)[0] + "/") for cls in MAX_PAYLOAD_BYTES if cls not in _JSON_KINDS
}

_msgpack_encoder = msgspec.msgpack.Encoder()
_json_encoder = msgspec.json.Encoder()
_decoders: dict[type, Any] = {
    cls: (msgspec.json.Decoder(cls) if cls in _JSON_KINDS else msgspec.msgpack.Decoder(cls)) for cls in MAX_PAYLOAD_BYTES
}

REASONS = ("malformed", "truncated", "oversized", "wrong_version", "invalid")


class DecodeStats:
    """Thread-safe counters of dropped payloads by (kind name, reason) and of good ones by kind.

    Reasons: ``oversized`` (above MAX_PAYLOAD_BYTES), ``truncated`` (ends mid-message), ``wrong_version`` (same
    message family, other schema version), ``invalid`` (well-formed but fails a check, e.g. NaN position),
    ``malformed`` (anything else: random bytes, wrong type).
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.dropped: Counter[tuple[str, str]] = Counter()
        self.ok: Counter[str] = Counter()

    def count_ok(self, kind: str) -> None:
        with self._lock:
            self.ok[kind] += 1

    def count_drop(self, kind: str, reason: str) -> None:
        with self._lock:
            self.dropped[(kind, reason)] += 1

    def dropped_total(self, reason: str | None = None) -> int:
        with self._lock:
            return sum(v for (_, r), v in self.dropped.items() if reason is None or r == reason)

    def snapshot(self) -> dict[str, dict[str, int]]:
        """{"ok": {kind: n}, "dropped": {"kind/reason": n}} for logs and metrics."""
        with self._lock:
            return {"ok": dict(self.ok), "dropped": {f"{k}/{r}": v for (k, r), v in self.dropped.items()}}


decode_stats = DecodeStats()


def encode(msg: Message) -> bytes:
    """Serialise a message: GeoJSON (UTF-8 JSON) for FloodPolygon, MessagePack for everything else."""
    if isinstance(msg, FloodPolygon):
        return _json_encoder.encode(msg)
    return _msgpack_encoder.encode(msg)


def _kind_class(kind: type[M] | str) -> type[M]:
    return KINDS[kind] if isinstance(kind, str) else kind


def _classify(cls: type, payload: bytes, error: Exception) -> str:
    if isinstance(error, InvalidMessage) or isinstance(error.__cause__, InvalidMessage):
        return "invalid"
    if "truncated" in str(error):
        return "truncated"
    if isinstance(error, msgspec.ValidationError):
        schema = _peek_schema(cls, payload)
        if schema is not None:
            family = "fw/polygon/" if cls in _JSON_KINDS else _SCHEMA_FAMILY[cls]
            current = "fw/polygon/1" if cls in _JSON_KINDS else cls.__struct_config__.tag
            if schema.startswith(family) and schema != current:
                return "wrong_version"
    return "malformed"


def _peek_schema(cls: type, payload: bytes) -> str | None:
    """The schema string of a payload that failed validation (only on the error path)."""
    try:
        raw = msgspec.json.decode(payload) if cls in _JSON_KINDS else msgspec.msgpack.decode(payload)
    except Exception:
        return None
    if not isinstance(raw, dict):
        return None
    if cls in _JSON_KINDS:
        props = raw.get("properties")
        value = props.get("schema") if isinstance(props, dict) else None
    else:
        value = raw.get("schema")
    return value if isinstance(value, str) else None


def decode_with_reason(kind: type[M] | str, payload: bytes | bytearray | memoryview, stats: DecodeStats | None = None) -> tuple[M | None, str | None]:
    """Like ``decode`` but also returns the drop reason (None when the message is good)."""
    s = decode_stats if stats is None else stats
    try:
        cls = _kind_class(kind)
        limit = MAX_PAYLOAD_BYTES[cls]
    except (KeyError, TypeError):
        s.count_drop(str(kind), "malformed")
        return None, "malformed"
    name = cls.__name__
    if len(payload) > limit:
        s.count_drop(name, "oversized")
        return None, "oversized"
    try:
        msg = _decoders[cls].decode(payload)
    except Exception as error:  # msgspec.DecodeError / ValidationError, and InvalidMessage from __post_init__
        reason = _classify(cls, bytes(payload), error)
        s.count_drop(name, reason)
        return None, reason
    s.count_ok(name)
    return msg, None


def decode(kind: type[M] | str, payload: bytes | bytearray | memoryview, stats: DecodeStats | None = None) -> M | None:
    """Parse a payload of a known kind (class or class name); None (and one count in ``stats``) on bad input.

    Never raises. ``stats`` defaults to the process-wide ``decode_stats``.
    """
    return decode_with_reason(kind, payload, stats)[0]
