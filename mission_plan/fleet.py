"""Who flies and where each vehicle stands: the ``[fleet]`` table turned into vehicles with launch pads.

Pads (SPEC §4): all vehicles start from one launch site, pads ``pad_spacing_m`` apart. The boundary drones stand in
a column along the edge tangent through the launch point, group A on the counter-clockwise side (rank 0 furthest,
it leads), group B on the clockwise side; the leader and the followers stand in columns behind them, away from
the flood, the leader in the middle of the first column (nearest the line it will fly in on).

This is plan, not resolution: given the launch site and the flood's centre it is pure geometry. Only
``launch_en_m = "auto"`` needs the flood model; the ground station fills it in first (``gcs.scenario``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from mission_plan.roles import ROLE_BOUNDARY, ROLE_FOLLOWER, ROLE_LEADER
from mission_plan.roster import RosterEntry
from mission_plan.table_fields import ScenarioError, integer, number, pair, reject_unknown

FLEET_KEYS = frozenset({"boundary_per_group", "leaders", "follower_layers", "pad_spacing_m", "launch_en_m",
                        "flood_center_en_m", "gps", "launch_bearing_deg", "launch_clearance_m", "pad_jitter_m", "start_jitter_s"})
GPS_CHOICES = (ROLE_LEADER.value, "all", "none")
AUTO_LAUNCH = "auto"
"""``launch_en_m = "auto"``: the launch site just outside the flood's initial edge (resolved by the ground station)."""


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
        """What every other drone knows of this one."""
        return RosterEntry(self.vehicle_id, self.role, self.group, self.rank, self.layer, self.ref_id, self.has_gps,
                           (self.pad_enu_m[0], self.pad_enu_m[1]))


def check_fleet_keys(fleet: Mapping[str, Any]) -> None:
    """Reject unknown ``[fleet]`` keys (before anything reads the table, so a typo never reaches the flood model)."""
    reject_unknown(fleet, FLEET_KEYS, "fleet")


@dataclass(frozen=True)
class _Layout:
    """The checked ``[fleet]`` table: group size, leaders, follower layers, and the pad grid's origin and axes."""

    per_group: int
    leaders: int
    layers: tuple[int, ...]
    spacing_m: float
    launch_en_m: tuple[float, float]
    radial: tuple[float, float]
    tangent: tuple[float, float]
    gps: str

    def pad(self, column: float, along_m: float) -> tuple[float, float, float]:
        """The pad ``column`` spacings from the launch site away from the flood, ``along_m`` across [m; ENU]."""
        out = self.spacing_m * column
        return (self.launch_en_m[0] + self.radial[0] * out + self.tangent[0] * along_m,
                self.launch_en_m[1] + self.radial[1] * out + self.tangent[1] * along_m, 0.0)


def _layout(fleet: Mapping[str, Any]) -> _Layout:
    check_fleet_keys(fleet)
    if fleet.get("launch_en_m") == AUTO_LAUNCH:
        raise ScenarioError('fleet.launch_en_m: "auto" pads need the flood model: use a plan file '
                            "(python -m gcs.plan SCENARIO --out DIR writes them)")
    per_group = integer(fleet, "boundary_per_group", 4, "fleet", minimum=1)
    leaders = integer(fleet, "leaders", 1, "fleet")
    layers_raw = fleet.get("follower_layers", [4])
    if not isinstance(layers_raw, list) or not all(isinstance(n, int) and not isinstance(n, bool) and n >= 1
                                                   for n in layers_raw):
        raise ScenarioError(f"fleet.follower_layers: must be a list of positive integers, got {layers_raw!r}")
    if layers_raw and leaders < 1:
        raise ScenarioError("fleet.leaders: followers need a leader (eq 10 targets lie on the leader's segments)")
    spacing = number(fleet, "pad_spacing_m", 1.5, "fleet", positive=True)
    launch = pair(fleet, "launch_en_m", (14.0, 0.0), "fleet")
    centre = pair(fleet, "flood_center_en_m", (0.0, 0.0), "fleet")
    gps = fleet.get("gps", ROLE_LEADER.value)
    if gps not in GPS_CHOICES:
        raise ScenarioError(f"fleet.gps: must be leader, all or none, got {gps!r}")
    number(fleet, "launch_bearing_deg", 0.0, "fleet")
    number(fleet, "launch_clearance_m", 2.0, "fleet", non_negative=True)
    rx, ry = launch[0] - centre[0], launch[1] - centre[1]
    norm = math.hypot(rx, ry)
    if norm < 1e-6:
        raise ScenarioError("fleet.launch_en_m: the launch site must not be the flood centre")
    radial = (rx / norm, ry / norm)
    return _Layout(per_group, leaders, tuple(layers_raw), spacing, launch, radial, (-radial[1], radial[0]), str(gps))


def build_fleet(fleet: Mapping[str, Any]) -> tuple[VehicleSpec, ...]:
    """Vehicles and pads from a ``[fleet]`` table (see module doc); ids are 1-based in the order A, B, leaders, followers.

    ``launch_en_m`` must be a pair here; ``"auto"`` raises (the ground station resolves it with the flood model).
    Boundary pads line the launch site's front row, group A on one side and B on the other; leaders and followers
    fill the rows behind, nearest the middle first.
    """
    lay = _layout(fleet)
    per_group, spacing = lay.per_group, lay.spacing_m
    vehicles = [VehicleSpec(1 + g * per_group + rank, ROLE_BOUNDARY,
                            lay.pad(0, sign * spacing * (per_group - rank - 0.5)), lay.gps == "all", group=group,
                            rank=rank)
                for g, (group, sign) in enumerate((("A", 1.0), ("B", -1.0))) for rank in range(per_group)]
    ring = [*sorted((v for v in vehicles if v.group == "B"), key=lambda v: v.rank),
            *sorted((v for v in vehicles if v.group == "A"), key=lambda v: -v.rank)]
    column_len = 2 * per_group
    inner_count = lay.leaders + sum(lay.layers)
    slots = iter(sorted(
        ((1 + k // column_len, spacing * ((k % column_len) - (column_len - 1) / 2.0))
         for k in range(inner_count + column_len)),
        key=lambda slot: (slot[0], abs(slot[1]), slot[1]),
    )[:inner_count])
    for _ in range(lay.leaders):
        vehicles.append(VehicleSpec(len(vehicles) + 1, ROLE_LEADER, lay.pad(*next(slots)),
                                    lay.gps in (ROLE_LEADER, "all")))
    outer_ids = [v.vehicle_id for v in ring]
    for layer, count in enumerate(lay.layers, start=1):
        n = len(outer_ids) / count
        ids = []
        for j in range(count):
            ref = (outer_ids[min(len(outer_ids) - 1, int(round(n * (j + 1))) - 1)] if layer == 1
                   else outer_ids[int(j * n)])
            ids.append(len(vehicles) + 1)
            vehicles.append(VehicleSpec(ids[-1], ROLE_FOLLOWER, lay.pad(*next(slots)), lay.gps == "all",
                                        layer=layer, ref_id=ref))
        outer_ids = ids
    return tuple(vehicles)
