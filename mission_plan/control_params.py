"""Control parameters of one mission mode (the part of the mission plan every control step reads).

Gains are in metres and seconds (SPEC §2): ``k_*_per_s`` is the inverse of a time constant. The paper's
``K = diag(1/300, 1/85)`` only makes sense in image pixels; it is kept as the ``paper_pixels`` gain preset
(:data:`PAPER_PIXEL_GAINS`), which in metres gives time constants of minutes.

The roster (:class:`mission_plan.roster.RosterEntry`) travels inside the parameters: it is knowledge each drone
legitimately has before take-off, who flies which role, the boundary groups and their order of departure, and
which vehicle each follower tracks (eq 10's ``i = n j``).
"""

from __future__ import annotations

import enum

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from types import MappingProxyType
from typing import Any

from mission_plan.roles import ROLE_BOUNDARY, ROLE_FOLLOWER, ROLES
from mission_plan.roster import RosterEntry
from mission_plan.unknown_keys import first_unknown, unknown_key_message

class ControlMode(enum.StrEnum):
    """The control-law sets a mission flies: the paper's laws as printed, or with the improvements (ring spacing,
    the braking-aware barrier, the area-centroid leader). Equal to its name in plans and on the command line."""

    PAPER = "paper"
    IMPROVED = "improved"


MODES: tuple[ControlMode, ...] = tuple(ControlMode)
PDOT_READINGS = ("normal", "full", "none")
PAPER_PIXEL_GAINS = (1.0 / 300.0, 1.0 / 85.0)
"""Eq 8 as printed: K_b = K_l = K_f = diag(1/300, 1/85) (the paper's §IV values, pixel units)."""
GAIN_PRESETS = ("metres", "paper_pixels")


class ControlParamsError(ValueError):
    """A control parameter is out of range; the message names the field."""


@dataclass(frozen=True)
class ControlParams:
    """Everything a control step needs besides its inputs. Defaults are the ``paper`` mode in metres."""

    mode: str = ControlMode.PAPER
    nominal_altitude_m: float = 10.0
    fov_deg: float = 60.0
    k_boundary_per_s: tuple[float, float] = (1.0, 1.0)
    """K_b of eq 5 as diag(k_normal, k_tangent)... applied on world axes (east, north) as the paper writes it."""
    k_leader_per_s: tuple[float, float] = (0.6, 0.6)
    k_follower_per_s: tuple[float, float] = (0.6, 0.6)
    separation_distance_m: float = 10.0
    """d of eq 7."""
    separation_gain_mps: float = 1.0
    """|v| of eq 6 (and |ω| of eq 10): the push at zero distance [m/s]."""
    encircle_speed_mps: float = 1.0
    """|u_c| of eq 4 (paper §IV: 1 m/s)."""
    pdot_reading: str = "normal"
    """Which ṗ eq 5 feeds forward: the edge-normal part ("normal"), all of it ("full", positive feedback), or none."""
    pdot_filter_time_s: float = 1.0
    climb_speed_mps: float = 1.0
    descent_speed_mps: float = 0.5
    k_altitude_per_s: float = 1.0
    max_altitude_m: float = 40.0
    """Algorithm 1 never climbs above this."""
    max_speed_mps: float = 5.0
    meet_distance_m: float = 10.0
    """The two groups' leading drones meet (encircling completes) when they hear each other this close."""
    min_encircle_travel_m: float = 8.0
    """A leading drone must have flown this far along the edge before a meeting counts (not at the launch site)."""
    neighbour_timeout_s: float = 3.0
    """Without the neighbour filter: a neighbour whose newest message is older than this is dropped."""
    neighbour_filter: bool = False
    """Improved: the laws read a constant-velocity Kalman estimate of each neighbour, predicted to the control time,
    and a neighbour is dropped when its position uncertainty exceeds ``neighbour_position_bound_m``."""
    neighbour_accel_psd_m2ps3: float = 1.0
    """The filter's process noise: white acceleration of this spectral density [m²/s³] per horizontal axis."""
    neighbour_position_std_m: float = 0.3
    neighbour_velocity_std_mps: float = 0.3
    """The filter's measurement noise: how well a drone knows its own position and velocity (GPS, odometry)."""
    neighbour_position_bound_m: float = 3.0
    """The filter drops a neighbour whose predicted position standard deviation exceeds this [m]."""
    relay_max_hops: int = 0
    """Improved: drones relay what they heard, up to this many hops from the origin (0: no relay)."""
    relay_max_age_s: float = 2.0
    """A relayed state older than this (by its origin's time stamp) is not relayed further."""
    relay_budget_bytes: int = 3000
    """At most this many encoded bytes of relayed states ride on one state message."""
    state_rate_hz: float = 20.0
    """How many state messages a drone sends per mission second (the scenario's ``control_rate_hz``): a relayed
    copy's ``seq`` cannot run ahead of what its origin could have sent (:mod:`vehicle_agents.core.relay_admission`)."""
    relay_every: int = 1
    """Relayed states ride on one state message in this many: 4 cuts the relay's traffic and cost fourfold (on
    ``circle`` at 15 m range the polygon IoU went from 0.997 to 0.989 at 30 s; docs/COMMS.md)."""
    follower_cover_fraction: float = 0.9
    """A layer of footprints covers this fraction of a footprint side radially (for the layer-release test)."""
    spacing_gain_per_s: float = 0.8
    """Improved: gain of the equal-gap consensus along the ring."""
    safety_radius_m: float = 5.0
    """Improved: every role pushes away from any vehicle closer than this."""
    safety_gain_mps: float = 3.0
    safety_min_distance_m: float = 2.5
    """Improved: the barrier filter never lets a command close a gap below this."""
    safety_closing_rate_per_s: float = 1.0
    safety_braking_mps2: float = 2.0
    """Improved: the deceleration the barrier counts on (PX4's MPC_ACC_HOR is 3 m/s²; the rest is margin)."""
    safety_reaction_s: float = 0.5
    """Improved: how long a drone keeps closing before it brakes: control period, PX4's velocity response, radio."""
    cooperative_position: bool = False
    """Improved: drones without GPS correct their drifting odometry from the relative positions they sense of their
    neighbours (:mod:`vehicle_agents.core.cooperative_position`); only while ``odometry_drift_frac`` > 0."""
    odometry_drift_frac: float = 0.0
    """The drone's odometry drift [fraction of the distance flown]: its own sensor's figure (``[sensors]``)."""
    ranging_sigma_m: float = 0.1
    """σ per axis of the relative-position sensor [m] (``[sensors]``)."""
    ranging_available: bool = False
    """The drone's relative-position sensor is read (``[sensors]``: while position estimates err)."""
    sensed_barrier: bool = False
    """Improved: the collision barrier keeps clear of neighbours where the relative-position sensor sees them, not
    where their broadcast and this drone's own estimate put them (a GPS fix 1 m off makes a pad neighbour 1.4 m
    away look 2.3 m away); only while ``ranging_available``."""
    edge_point_tracking: bool = False
    """Improved: track the edge points the camera sees under the drone instead of the land/water midpoint."""
    roster: tuple[RosterEntry, ...] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ControlParamsError(f"control.mode: must be one of {', '.join(MODES)}, got {self.mode!r}")
        if self.pdot_reading not in PDOT_READINGS:
            raise ControlParamsError(
                f"control.pdot_reading: must be one of {', '.join(PDOT_READINGS)}, got {self.pdot_reading!r}"
            )
        for name in ("nominal_altitude_m", "max_altitude_m", "fov_deg", "separation_distance_m", "max_speed_mps", "pdot_filter_time_s"):
            if not getattr(self, name) > 0.0:
                raise ControlParamsError(f"control.{name}: must be > 0, got {getattr(self, name)}")
        if self.fov_deg >= 180.0:
            raise ControlParamsError(f"control.fov_deg: must be < 180, got {self.fov_deg}")
        for name in ("encircle_speed_mps", "separation_gain_mps", "climb_speed_mps", "descent_speed_mps",
                     "meet_distance_m", "min_encircle_travel_m", "spacing_gain_per_s", "safety_radius_m",
                     "safety_gain_mps", "safety_min_distance_m", "safety_closing_rate_per_s", "safety_braking_mps2",
                     "safety_reaction_s", "neighbour_timeout_s", "k_altitude_per_s", "neighbour_accel_psd_m2ps3",
                     "relay_max_hops", "relay_max_age_s", "relay_budget_bytes", "relay_every", "odometry_drift_frac",
                     "ranging_sigma_m"):
            if not getattr(self, name) >= 0.0:
                raise ControlParamsError(f"control.{name}: must be >= 0, got {getattr(self, name)}")
        for name in ("neighbour_position_std_m", "neighbour_velocity_std_mps", "neighbour_position_bound_m",
                     "state_rate_hz"):
            if not getattr(self, name) > 0.0:
                raise ControlParamsError(f"control.{name}: must be > 0, got {getattr(self, name)}")
        for name in ("k_boundary_per_s", "k_leader_per_s", "k_follower_per_s"):
            gains = getattr(self, name)
            if len(gains) != 2 or not all(g > 0.0 for g in gains):
                raise ControlParamsError(f"control.{name}: must be two gains > 0, got {gains!r}")
        for entry in self.roster:
            if entry.role not in ROLES:
                raise ControlParamsError(f"vehicles.{entry.vehicle_id}.role: unknown role {entry.role!r}")

    def entry(self, vehicle_id: int) -> RosterEntry:
        """This vehicle's roster entry; a vehicle the roster does not hold is an error (KeyError naming it)."""
        for entry in self.roster:
            if entry.vehicle_id == vehicle_id:
                return entry
        known = ", ".join(str(e.vehicle_id) for e in self.roster) or "none"
        raise KeyError(f"vehicle {vehicle_id} is not in the roster (vehicles: {known})")

    def ring_order(self) -> tuple[int, ...]:
        """Boundary drone ids in counter-clockwise order once caged: B's leader first, then B, then A back to A's leader.

        Group B leaves clockwise and group A counter-clockwise from the launch site, so going counter-clockwise from
        B's leading drone one meets B's ranks 0..n, A's ranks n..0, and then B's leader again.
        """
        return self._ring_order

    def followers(self) -> tuple[RosterEntry, ...]:
        return self._followers

    @cached_property
    def rank_of(self) -> Mapping[int, int]:
        """Vehicle id -> departure rank, for every roster entry (the control laws look ranks up every step)."""
        return MappingProxyType({e.vehicle_id: e.rank for e in self.roster})

    # The roster never changes (the parameters are frozen), and the laws ask for these every step of every drone:
    # computed once per parameter set (a cached_property keeps them out of the fields, equality and the plan files).
    @cached_property
    def _ring_order(self) -> tuple[int, ...]:
        b = sorted((e for e in self.roster if e.role == ROLE_BOUNDARY and e.group == "B"), key=lambda e: e.rank)
        a = sorted((e for e in self.roster if e.role == ROLE_BOUNDARY and e.group == "A"), key=lambda e: -e.rank)
        return tuple(e.vehicle_id for e in (*b, *a))

    @cached_property
    def _followers(self) -> tuple[RosterEntry, ...]:
        return tuple(e for e in self.roster if e.role == ROLE_FOLLOWER)


_IMPROVED_DEFAULTS: dict[str, Any] = {
    "encircle_speed_mps": 3.0,
    "edge_point_tracking": True,
    "neighbour_filter": True,
    "relay_max_hops": 3,
    "cooperative_position": True,
    "sensed_barrier": True,
}


def _tunable_keys(fixed: Mapping[str, Any]) -> frozenset[str]:
    """The parameters a ``[control]`` table may set: every field but the mode, the roster and the fixed ones."""
    return frozenset(ControlParams.__dataclass_fields__) - {"mode", "roster"} - set(fixed)


def _check_keys(table: Mapping[str, Any], fixed: Mapping[str, Any]) -> None:
    """Reject unknown keys in ``[control]`` and in its ``[control.paper]`` / ``[control.improved]`` sub-tables.

    Both sub-tables are checked whichever mode is built, so a typo in the mode not flown still stops the run.
    A key the scenario fixes elsewhere (the altitude, the camera's field of view) would be silently overridden,
    so it is refused with the place it comes from.
    """
    tunable = _tunable_keys(fixed)
    for where, sub, known in (("control", table, tunable | {"gain_preset", *MODES}),
                              *((f"control.{m}", table.get(m, {}), tunable | {"gain_preset"}) for m in MODES)):
        if not isinstance(sub, Mapping):
            raise ControlParamsError(f"{where}: must be a table, got {sub!r}")
        for key in sub:
            if key in fixed:
                raise ControlParamsError(f"{where}.{key}: set by the scenario, not by the [control] table")
        unknown = first_unknown(sub, known)
        if unknown is not None:
            raise ControlParamsError(unknown_key_message(where, unknown, known))


def params_for_mode(mode: str, table: Mapping[str, Any], roster: tuple[RosterEntry, ...], **fixed: Any) -> ControlParams:
    """Build the parameters of one mode from a scenario's ``[control]`` table.

    Keys at the top of the table apply to both modes; ``[control.paper]`` and ``[control.improved]`` sub-tables
    override them for one mode. The improved mode starts from :data:`_IMPROVED_DEFAULTS` (a 3 m/s encircling
    speed, edge-point tracking). ``gain_preset = "paper_pixels"`` selects the paper's printed gains. ``fixed``
    are the values the scenario sets elsewhere (``nominal_altitude_m``, ``fov_deg``). Raises
    :class:`ControlParamsError` naming the field; an unknown key names the closest known one.
    """
    if mode not in MODES:
        raise ControlParamsError(f"mode: must be one of {', '.join(MODES)}, got {mode!r}")
    _check_keys(table, fixed)
    values: dict[str, Any] = dict(_IMPROVED_DEFAULTS) if mode == ControlMode.IMPROVED else {}
    merged: dict[str, Any] = {k: v for k, v in table.items() if k not in MODES}
    merged.update(table.get(mode, {}) or {})
    preset = merged.pop("gain_preset", "metres")
    if preset == "paper_pixels":
        values.update(k_boundary_per_s=PAPER_PIXEL_GAINS, k_leader_per_s=PAPER_PIXEL_GAINS,
                      k_follower_per_s=PAPER_PIXEL_GAINS)
    elif preset != "metres":
        raise ControlParamsError(f"control.gain_preset: must be {' or '.join(GAIN_PRESETS)}, got {preset!r}")
    for key, value in merged.items():
        default = ControlParams.__dataclass_fields__[key].default
        try:
            if isinstance(default, tuple):
                value = tuple(float(v) for v in (value if isinstance(value, (list, tuple)) else (value, value)))
            elif isinstance(default, bool):
                if not isinstance(value, bool):
                    raise TypeError
            elif isinstance(default, float):
                value = float(value)
            elif isinstance(default, int):
                if isinstance(value, bool) or not isinstance(value, int):
                    raise TypeError
            elif isinstance(default, str):
                value = str(value)
        except (TypeError, ValueError):
            raise ControlParamsError(f"control.{key}: bad value {value!r}") from None
        values[key] = value
    values.update(fixed)
    return ControlParams(mode=mode, roster=roster, **values)
