"""Which camera results a boundary drone acts on: one frame that contradicts a recent edge is doubted, not obeyed.

A flood's edge moves slowly (centimetres per second) while frames arrive at 2-10 Hz, so a frame whose edge lies
metres across the normal from where the drone last saw it, a frame whose edge runs in a direction turned far from
the last one (the edge of a cloud shadow across turbid water read as a second shore bends the edge points' axis by
tens of degrees), or a frame of only land or only water while that edge should still be in view, is far more likely
a misread frame (shadow, glint, a compression block) than the world.
Acting on it would make the drone dart across the shore, or search and climb (Algorithm 1, line 8) and lose the
edge for several seconds. Such a frame is replaced by "no measurement", so the drone holds its track (keeps moving
along the last tangent at its altitude).

A contradicting edge is believed once it has stood still: frames over ``TrustLimits.hold_s`` have seen it within
``candidate_spread_m`` (plus ``candidate_speed_mps`` per second) of where it was first seen. A flood's edge that
the drone misjudged stands still; the edge of a cloud shadow drifts with the wind at metres per second, so it keeps
restarting and is never obeyed, however many frames read it. The trusted edge's own allowance widens with its age
(``edge_speed_mps`` past ``hold_s``, ``turn_rate_radps``), so a drone that has seen no edge it trusts for seconds
takes the next edge near it; a frame of one class is doubted only within ``hold_s`` of the last trusted edge.

Pure: the drone's own position estimate and time in, the result to act on and the new memory out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from vehicle_agents.perception.result import PerceptionResult


@dataclass(frozen=True)
class TrustLimits:
    """How far a frame may disagree with the last trusted edge before it is doubted, and for how long."""

    hold_s: float = 1.0
    """A contradicting edge is believed once it has stood still this long; a one-class frame is doubted at most
    this long after the last trusted edge [s]."""
    max_jump_m: float = 2.0
    """An edge further across its normal than this from the last trusted one is doubted [m] (own position noise
    between two frames and the footprint's edge effects stay well inside it) ..."""
    edge_speed_mps: float = 1.0
    """... plus this speed times the time past ``hold_s`` since the last trusted edge (a drone that has trusted no
    edge for that long, searching or climbing, takes the next one near it). Within ``hold_s`` the limit stands
    still: the doubt is about frames, not about the world, and a limit that widened with each tick would let in at
    its second look a misread frame held at its first (frames come at half the control rate)."""
    max_turn_rad: float = math.radians(35.0)
    """An edge whose normal is turned further than this from the last trusted one is doubted [rad] ..."""
    turn_rate_radps: float = 0.5
    """... plus this rate times the time since the last trusted edge (a drone flying round a bend: 3 m/s along a
    12 m radius turns the normal by 0.25 rad/s; the normal is fitted over a footprint of edge, which smooths
    corners)."""
    candidate_spread_m: float = 1.0
    """A contradicting edge stands still while each frame sees it within this distance across its normal of where
    it was first seen [m] (own position noise between frames, pixel noise) ..."""
    candidate_speed_mps: float = 0.5
    """... plus this speed times the time since then (a flood's edge, even a fast one; a cloud shadow's edge moves
    with the wind, 5-9 m/s in the weather presets)."""
    in_view_fraction: float = 0.35
    """A one-class frame is doubted while the last edge lies within this share of the footprint side from the point
    below the drone across the normal (well inside the image, which reaches half the side)."""


@dataclass(frozen=True)
class EdgeTrust:
    """The last edge a drone trusted: a point of it [m; mission E, N], its normal (water to land), and when; and the
    contradicting edge it is watching (where and when first seen), if any."""

    edge_en_m: tuple[float, float] | None = None
    normal_en: tuple[float, float] | None = None
    t_s: float = -math.inf
    candidate_en_m: tuple[float, float] | None = None
    candidate_normal_en: tuple[float, float] | None = None
    candidate_t_s: float = -math.inf


NO_TRUST = EdgeTrust()


def edge_point_en_m(result: PerceptionResult, own_en_m: np.ndarray) -> tuple[float, float] | None:
    """The edge seen, as a mission point: the median of the edge points across the normal (the midpoint offset
    when there are none), placed from the drone's own position estimate."""
    if result.edge_normal_en is None or result.midpoint_offset_en_m is None:
        return None
    normal = np.asarray(result.edge_normal_en, float)
    points = np.asarray(result.edge_points_en_m, float).reshape(-1, 2)
    across = float(np.median(points @ normal)) if len(points) else float(np.asarray(result.midpoint_offset_en_m) @ normal)
    point = np.asarray(own_en_m, float) + across * normal
    return float(point[0]), float(point[1])


def trusted_result(result: PerceptionResult | None, own_en_m: np.ndarray, t_s: float, trust: EdgeTrust,
                   limits: TrustLimits = TrustLimits()) -> tuple[PerceptionResult | None, EdgeTrust]:
    """(the result to act on, the new memory) for a drone at ``own_en_m`` [m; mission E, N] at ``t_s`` [s]."""
    if result is None:
        return None, trust
    if result.has_edge:
        point = edge_point_en_m(result, own_en_m)
        if point is None:
            return result, trust
        normal = np.asarray(result.edge_normal_en, float)
        seen = EdgeTrust(point, (float(normal[0]), float(normal[1])), t_s)
        if trust.edge_en_m is None or trust.normal_en is None or not _contradicts(
                point, normal, t_s - trust.t_s, trust.edge_en_m, trust.normal_en,
                limits.max_jump_m, limits.edge_speed_mps, limits, limits.hold_s):
            return result, seen
        if trust.candidate_en_m is None or trust.candidate_normal_en is None or _contradicts(
                point, normal, t_s - trust.candidate_t_s, trust.candidate_en_m, trust.candidate_normal_en,
                limits.candidate_spread_m, limits.candidate_speed_mps, limits):
            watched = replace(trust, candidate_en_m=seen.edge_en_m, candidate_normal_en=seen.normal_en,
                              candidate_t_s=t_s)
            return PerceptionResult.no_measurement(result.footprint_side_m), watched
        if t_s - trust.candidate_t_s >= limits.hold_s:
            return result, seen
        return PerceptionResult.no_measurement(result.footprint_side_m), trust
    recent = trust.edge_en_m is not None and trust.normal_en is not None and t_s - trust.t_s <= limits.hold_s
    if (result.only_land or result.only_water) and recent:
        across_m = abs(float(np.subtract(own_en_m, trust.edge_en_m) @ np.asarray(trust.normal_en)))
        if across_m <= limits.in_view_fraction * result.footprint_side_m:
            return PerceptionResult.no_measurement(result.footprint_side_m), trust
    return result, trust


def _contradicts(point: tuple[float, float], normal: np.ndarray, age_s: float, reference_en_m: tuple[float, float],
                 reference_normal_en: tuple[float, float], max_jump_m: float, speed_mps: float,
                 limits: TrustLimits, still_s: float = 0.0) -> bool:
    """Whether an edge seen at ``point`` with ``normal`` lies further across than ``max_jump_m`` plus ``speed_mps``
    per second of ``age_s`` past ``still_s``, or runs turned further than the turn limits allow, from a reference
    edge seen ``age_s`` earlier."""
    age_s = max(age_s, 0.0)
    reference_normal = np.asarray(reference_normal_en)
    jump_m = abs(float(np.subtract(point, reference_en_m) @ reference_normal))
    if jump_m > max_jump_m + speed_mps * max(age_s - still_s, 0.0):
        return True
    cos_turn = float(normal @ reference_normal) / max(float(np.hypot(normal[0], normal[1])), 1e-12)
    return cos_turn < math.cos(min(limits.max_turn_rad + limits.turn_rate_radps * age_s, math.pi))
