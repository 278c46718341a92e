"""Scenarios: TOML files in ``gcs/scenarios/`` turned into a frozen :class:`Scenario`, with ``key=value`` overrides.

A scenario says where the mission is (``[home]``), what floods (``[flood]``, read by the world team's
``flood_model_from_config``), who flies (``[fleet]``: how many boundary drones per group, leaders, followers per
layer, the launch site and pad spacing), the camera (``[camera]``), the radio (``[radio]``), the vehicle limits
(``[kinematics]``) and the control parameters (``[control]``, with ``[control.paper]``/``[control.improved]``).

Pads (SPEC §4): all vehicles start from one launch site, pads ``pad_spacing_m`` apart. The boundary drones stand in
a column along the edge tangent through the launch point, group A on the counter-clockwise side (rank 0 furthest,
it leads), group B on the clockwise side; the leader and the followers stand in columns behind them, away from
the flood, the leader in the middle of the first column (nearest the line it will fly in on). ``launch_en_m = "auto"`` puts the launch site just outside the initial edge (see :func:`auto_launch`).
Any error raises :class:`ScenarioError` whose one-line message names the field.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping, Sequence

from comms.frames import GeodeticHome
from mock_autopilot.kinematics import KinematicLimits
from mock_autopilot.world.config import flood_model_from_config
from vehicle_agents.control.params import ControlParams, ControlParamsError, RosterEntry, params_for_mode
from vehicle_agents.control.types import ROLE_BOUNDARY, ROLE_FOLLOWER, ROLE_LEADER

SCENARIO_DIR = Path(__file__).resolve().parent / "scenarios"


class ScenarioError(ValueError):
    """A scenario file or override is invalid; the message names the field."""


@dataclass(frozen=True)
class VehicleSpec:
    """One vehicle: id (1-based, also its MAVLink system id), role, roster extras, GPS, pad [m; mission E, N, U]."""

    vehicle_id: int
    role: str
    pad_enu_m: tuple[float, float, float]
    has_gps: bool
    group: str | None = None
    rank: int = 0
    layer: int = 0
    ref_id: int | None = None

    def roster_entry(self) -> RosterEntry:
        return RosterEntry(self.vehicle_id, self.role, self.group, self.rank, self.layer, self.ref_id, self.has_gps)


@dataclass(frozen=True)
class CameraSpec:
    """Downward camera: image size [px], field of view [deg] and frame rate [Hz of mission time].

    The frame rate is the camera's own, slower than the control loop as on a real drone: between frames the control
    law runs on the newest frame it has (both engines).
    """

    width_px: int = 128
    height_px: int = 128
    fov_deg: float = 60.0
    rate_hz: float = 10.0


@dataclass(frozen=True)
class RadioSpec:
    """Swarm radio: range [m], loss probability, latency and jitter [s]."""

    range_m: float = 25.0
    loss: float = 0.0
    latency_s: float = 0.0
    jitter_s: float = 0.0


@dataclass(frozen=True)
class Scenario:
    """A whole mission setup. ``flood`` and ``control`` stay tables (their owners validate them)."""

    name: str
    seed: int
    duration_s: float
    altitude_m: float
    home: GeodeticHome
    flood: Mapping[str, Any]
    vehicles: tuple[VehicleSpec, ...]
    camera: CameraSpec
    radio: RadioSpec
    kinematics: KinematicLimits
    control: Mapping[str, Any]
    control_rate_hz: float = 20.0
    polygon_period_s: float = 1.0
    source_dir: Path = field(default=SCENARIO_DIR)

    def roster(self) -> tuple[RosterEntry, ...]:
        return tuple(v.roster_entry() for v in self.vehicles)

    def control_params(self, mode: str) -> ControlParams:
        """The control parameters of ``mode`` ("paper" or "improved") for every vehicle of this scenario."""
        try:
            return params_for_mode(
                mode, self.control, self.roster(), nominal_altitude_m=self.altitude_m, fov_deg=self.camera.fov_deg
            )
        except ControlParamsError as exc:
            raise ScenarioError(str(exc)) from None


def scenario_names() -> list[str]:
    """Names of the bundled scenarios."""
    return sorted(p.stem for p in SCENARIO_DIR.glob("*.toml"))


def _parse_value(text: str) -> Any:
    """An override's value as TOML would read it (numbers, booleans, arrays, quoted strings); bare words are strings."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def apply_override(table: dict[str, Any], assignment: str) -> None:
    """Apply one ``dotted.key=value`` to a nested table in place."""
    key, sep, value = assignment.partition("=")
    key = key.strip()
    if not sep or not key or any(not part for part in key.split(".")):
        raise ScenarioError(f"--set {assignment!r}: expected key=value, e.g. flood.radius_end_m=20")
    parts = key.split(".")
    node = table
    for part in parts[:-1]:
        child = node.setdefault(part, {})
        if not isinstance(child, dict):
            raise ScenarioError(f"{key}: {part} is not a table")
        node = child
    node[parts[-1]] = _parse_value(value.strip())


def _number(table: Mapping[str, Any], key: str, default: float, where: str, *, positive: bool = False,
            non_negative: bool = False, maximum: float | None = None) -> float:
    value = table.get(key, default)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(float(value)):
        raise ScenarioError(f"{where}.{key}: must be a finite number, got {value!r}")
    value = float(value)
    if positive and value <= 0.0:
        raise ScenarioError(f"{where}.{key}: must be > 0, got {value:g}")
    if non_negative and value < 0.0:
        raise ScenarioError(f"{where}.{key}: must be >= 0, got {value:g}")
    if maximum is not None and value > maximum:
        raise ScenarioError(f"{where}.{key}: must be <= {maximum:g}, got {value:g}")
    return value


def _integer(table: Mapping[str, Any], key: str, default: int, where: str, minimum: int = 0) -> int:
    value = table.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise ScenarioError(f"{where}.{key}: must be an integer >= {minimum}, got {value!r}")
    return value


def _table(raw: Mapping[str, Any], key: str) -> dict[str, Any]:
    value = raw.get(key, {})
    if not isinstance(value, dict):
        raise ScenarioError(f"{key}: must be a table")
    return value


def _pair(table: Mapping[str, Any], key: str, default: tuple[float, float], where: str) -> tuple[float, float]:
    value = table.get(key, list(default))
    if not isinstance(value, (list, tuple)) or len(value) != 2 or not all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(float(v)) for v in value
    ):
        raise ScenarioError(f"{where}.{key}: must be a pair [east, north] of numbers, got {value!r}")
    return float(value[0]), float(value[1])


def auto_launch(fleet: Mapping[str, Any], flood_table: Mapping[str, Any], seed: int, source_dir: Path) -> dict[str, Any]:
    """``launch_en_m = "auto"``: the launch site just outside the flood's edge at t = 0, along ``launch_bearing_deg``.

    Takes the initial boundary point furthest along the bearing (counter-clockwise from east) from the flood's
    centroid and steps ``launch_clearance_m`` (default 2 m, as in `circle`: pads at 14 m for a 12 m flood)
    further out. Returns the fleet table with ``launch_en_m`` and ``flood_center_en_m`` filled in.
    """
    try:
        flood = flood_model_from_config(flood_table, seed=seed, base_dir=source_dir)
    except ValueError as exc:
        raise ScenarioError(str(exc)) from None
    bearing = math.radians(_number(fleet, "launch_bearing_deg", 0.0, "fleet"))
    clearance = _number(fleet, "launch_clearance_m", 2.0, "fleet", non_negative=True)
    centre = flood.centroid_en_m(0.0)
    ring = flood.boundary_en_m(0.0)
    direction = (math.cos(bearing), math.sin(bearing))
    rel = ring - centre
    vertex = ring[int((rel[:, 0] * direction[0] + rel[:, 1] * direction[1]).argmax())]
    out = vertex - centre
    out_norm = max(math.hypot(out[0], out[1]), 1e-9)
    launch = vertex + clearance * out / out_norm
    table = dict(fleet)
    table["launch_en_m"] = [float(launch[0]), float(launch[1])]
    table["flood_center_en_m"] = [float(centre[0]), float(centre[1])]
    return table


_FLEET_KEYS = {"boundary_per_group", "leaders", "follower_layers", "pad_spacing_m", "launch_en_m", "flood_center_en_m",
               "gps", "launch_bearing_deg", "launch_clearance_m"}


def build_fleet(fleet: Mapping[str, Any]) -> tuple[VehicleSpec, ...]:
    """Vehicles and pads from a ``[fleet]`` table (see module doc); ids are 1-based in the order A, B, leaders, followers."""
    per_group = _integer(fleet, "boundary_per_group", 4, "fleet", minimum=1)
    leaders = _integer(fleet, "leaders", 1, "fleet")
    layers_raw = fleet.get("follower_layers", [4])
    if not isinstance(layers_raw, list) or not all(isinstance(n, int) and not isinstance(n, bool) and n >= 1 for n in layers_raw):
        raise ScenarioError(f"fleet.follower_layers: must be a list of positive integers, got {layers_raw!r}")
    if layers_raw and leaders < 1:
        raise ScenarioError("fleet.leaders: followers need a leader (eq 10 targets lie on the leader's segments)")
    spacing = _number(fleet, "pad_spacing_m", 1.5, "fleet", positive=True)
    launch = _pair(fleet, "launch_en_m", (14.0, 0.0), "fleet")
    centre = _pair(fleet, "flood_center_en_m", (0.0, 0.0), "fleet")
    for key in sorted(set(fleet) - _FLEET_KEYS):
        raise ScenarioError(f"fleet.{key}: unknown parameter")
    gps = fleet.get("gps", "leader")
    if gps not in ("leader", "all", "none"):
        raise ScenarioError(f"fleet.gps: must be leader, all or none, got {gps!r}")
    rx, ry = launch[0] - centre[0], launch[1] - centre[1]
    norm = math.hypot(rx, ry)
    if norm < 1e-6:
        raise ScenarioError("fleet.launch_en_m: the launch site must not be the flood centre")
    radial = (rx / norm, ry / norm)
    tangent = (-radial[1], radial[0])

    def pad(column: int, along: float) -> tuple[float, float, float]:
        return (launch[0] + radial[0] * spacing * column + tangent[0] * along,
                launch[1] + radial[1] * spacing * column + tangent[1] * along, 0.0)

    vehicles: list[VehicleSpec] = []
    next_id = 1
    for group, sign in (("A", 1.0), ("B", -1.0)):
        for rank in range(per_group):
            vehicles.append(VehicleSpec(next_id, ROLE_BOUNDARY, pad(0, sign * spacing * (per_group - rank - 0.5)),
                                        gps == "all", group=group, rank=rank))
            next_id += 1
    boundary_a = [v for v in vehicles if v.group == "A"]
    boundary_b = [v for v in vehicles if v.group == "B"]
    ring = [*sorted(boundary_b, key=lambda v: v.rank), *sorted(boundary_a, key=lambda v: -v.rank)]
    column_len = 2 * per_group
    inner_count = leaders + sum(layers_raw)
    inner_slots = sorted(
        ((1 + k // column_len, spacing * ((k % column_len) - (column_len - 1) / 2.0))
         for k in range(inner_count + column_len)),
        key=lambda slot: (slot[0], abs(slot[1]), slot[1]),
    )[:inner_count]
    slot = 0
    for _ in range(leaders):
        vehicles.append(VehicleSpec(next_id, ROLE_LEADER, pad(*inner_slots[slot]), gps in ("leader", "all")))
        next_id += 1
        slot += 1
    outer_ids = [v.vehicle_id for v in ring]
    for layer, count in enumerate(layers_raw, start=1):
        n = len(outer_ids) / count
        ids = []
        for j in range(count):
            ref = outer_ids[min(len(outer_ids) - 1, int(round(n * (j + 1))) - 1)] if layer == 1 else outer_ids[int(j * n)]
            vehicles.append(VehicleSpec(next_id, ROLE_FOLLOWER, pad(*inner_slots[slot]), gps == "all",
                                        layer=layer, ref_id=ref))
            ids.append(next_id)
            next_id += 1
            slot += 1
        outer_ids = ids
    return tuple(vehicles)


def scenario_path(name_or_path: str) -> Path:
    """A bundled scenario's file, or the given path."""
    candidate = Path(name_or_path)
    if candidate.suffix == ".toml" or candidate.exists():
        if not candidate.is_file():
            raise ScenarioError(f"scenario: no such file {name_or_path}")
        return candidate
    bundled = SCENARIO_DIR / f"{name_or_path}.toml"
    if not bundled.is_file():
        raise ScenarioError(f"scenario: unknown scenario {name_or_path!r} (known: {', '.join(scenario_names())})")
    return bundled


def load_scenario(name_or_path: str, overrides: Sequence[str] = ()) -> Scenario:
    """Read a scenario by bundled name or path and apply ``key=value`` overrides (dotted keys into the tables)."""
    path = scenario_path(name_or_path)
    try:
        raw: dict[str, Any] = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"scenario: {path.name} is not valid TOML ({exc})") from None
    for assignment in overrides:
        apply_override(raw, assignment)
    return scenario_from_table(raw, default_name=path.stem, source_dir=path.resolve().parent)


_TOP_KEYS = {"name", "seed", "duration_s", "altitude_m", "control_rate_hz", "polygon_period_s", "home", "flood",
             "fleet", "camera", "radio", "kinematics", "control", "description"}


def scenario_from_table(raw: Mapping[str, Any], default_name: str = "scenario", source_dir: Path = SCENARIO_DIR) -> Scenario:
    """Validate a parsed scenario table (see module doc)."""
    unknown = sorted(set(raw) - _TOP_KEYS)
    if unknown:
        raise ScenarioError(f"{unknown[0]}: unknown scenario key")
    name = raw.get("name", default_name)
    if not isinstance(name, str) or not name:
        raise ScenarioError(f"name: must be a non-empty string, got {name!r}")
    seed = _integer(raw, "seed", 1, "scenario")
    home_t = _table(raw, "home")
    home = GeodeticHome(
        lat_deg=_number(home_t, "lat_deg", GeodeticHome.lat_deg, "home", maximum=90.0),
        lon_deg=_number(home_t, "lon_deg", GeodeticHome.lon_deg, "home", maximum=180.0),
        alt_m=_number(home_t, "alt_m", GeodeticHome.alt_m, "home"),
    )
    if home.lat_deg < -90.0 or home.lon_deg < -180.0:
        raise ScenarioError("home: latitude/longitude out of range")
    cam_t = _table(raw, "camera")
    camera = CameraSpec(
        width_px=_integer(cam_t, "width_px", 128, "camera", minimum=8),
        height_px=_integer(cam_t, "height_px", 128, "camera", minimum=8),
        fov_deg=_number(cam_t, "fov_deg", 60.0, "camera", positive=True, maximum=170.0),
        rate_hz=_number(cam_t, "rate_hz", 10.0, "camera", positive=True, maximum=1000.0),
    )
    radio_t = _table(raw, "radio")
    radio = RadioSpec(
        range_m=_number(radio_t, "range_m", 25.0, "radio", non_negative=True),
        loss=_number(radio_t, "loss", 0.0, "radio", non_negative=True, maximum=1.0),
        latency_s=_number(radio_t, "latency_s", 0.0, "radio", non_negative=True),
        jitter_s=_number(radio_t, "jitter_s", 0.0, "radio", non_negative=True),
    )
    kin_t = _table(raw, "kinematics")
    limits = KinematicLimits(**{
        key: _number(kin_t, key, getattr(KinematicLimits, key), "kinematics", positive=True)
        for key in KinematicLimits.__dataclass_fields__
    })
    extra = sorted(set(kin_t) - set(KinematicLimits.__dataclass_fields__))
    if extra:
        raise ScenarioError(f"kinematics.{extra[0]}: unknown parameter")
    flood = _table(raw, "flood")
    if "model" not in flood:
        raise ScenarioError("flood.model: missing (circle, ellipse, nonconvex, drift or terrain)")
    fleet = _table(raw, "fleet")
    if fleet.get("launch_en_m") == "auto":
        fleet = auto_launch(fleet, flood, seed, source_dir)
    scenario = Scenario(
        name=name,
        seed=seed,
        duration_s=_number(raw, "duration_s", 60.0, "scenario", positive=True),
        altitude_m=_number(raw, "altitude_m", 10.0, "scenario", positive=True),
        home=home,
        flood=flood,
        vehicles=build_fleet(fleet),
        camera=camera,
        radio=radio,
        kinematics=limits,
        control=_table(raw, "control"),
        control_rate_hz=_number(raw, "control_rate_hz", 20.0, "scenario", positive=True, maximum=1000.0),
        polygon_period_s=_number(raw, "polygon_period_s", 1.0, "scenario", positive=True),
        source_dir=source_dir,
    )
    for mode in ("paper", "improved"):
        scenario.control_params(mode)
    return scenario
