"""Which camera results a boundary drone acts on: one frame that contradicts a recent edge is doubted, not obeyed.

A flood's edge moves slowly (centimetres per second) while frames arrive at 2-10 Hz, so a frame whose edge lies
metres across the normal from where the drone last saw it, a frame whose edge runs in a direction turned far from
the last one (the edge of a cloud shadow across turbid water read as a second shore bends the edge points' axis by
tens of degrees), or a frame of only land or only water while that edge should still be in view, is far more likely
a misread frame (shadow, glint, a compression block) than the world.
Acting on it would make the drone dart across the shore, or search and climb (Algorithm 1, line 8) and lose the
edge for several seconds. Such a frame is replaced by "no measurement", so the drone holds its track (keeps moving
along the last tangent at its altitude) for at most ``TrustLimits.hold_s`` after the last trusted edge; a
contradiction that persists longer is the world and is acted on.

Pure: the drone's own position estimate and time in, the result to act on and the new memory out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vehicle_agents.perception.result import PerceptionResult


@dataclass(frozen=True)
class TrustLimits:
    """How far a frame may disagree with the last trusted edge before it is doubted, and for how long."""

    hold_s: float = 1.0
    """A contradicting frame is doubted at most this long after the last trusted edge [s]."""
    max_jump_m: float = 2.0
    """An edge further across its normal than this from the last trusted one is doubted [m] (own position noise
    between two frames and the footprint's edge effects stay well inside it) ..."""
    edge_speed_mps: float = 1.0
    """... plus this speed times the time since the last trusted edge (a rising flood, the drone's own drift)."""
    max_turn_rad: float = math.radians(35.0)
    """An edge whose normal is turned further than this from the last trusted one is doubted [rad] ..."""
    turn_rate_radps: float = 0.5
    """... plus this rate times the time since the last trusted edge (a drone flying round a bend: 3 m/s along a
    12 m radius turns the normal by 0.25 rad/s; the normal is fitted over a footprint of edge, which smooths
    corners)."""
    in_view_fraction: float = 0.35
    """A one-class frame is doubted while the last edge lies within this share of the footprint side from the point
    below the drone across the normal (well inside the image, which reaches half the side)."""


@dataclass(frozen=True)
class EdgeTrust:
    """The last edge a drone trusted: a point of it [m; mission E, N], its normal (water to land), and when."""

    edge_en_m: tuple[float, float] | None = None
    normal_en: tuple[float, float] | None = None
    t_s: float = -math.inf


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
    recent = trust.edge_en_m is not None and trust.normal_en is not None and t_s - trust.t_s <= limits.hold_s
    if result.has_edge:
        point = edge_point_en_m(result, own_en_m)
        if point is None:
            return result, trust
        normal = np.asarray(result.edge_normal_en, float)
        if recent and _contradicts(point, normal, t_s, trust, limits):
            return PerceptionResult.no_measurement(result.footprint_side_m), trust
        return result, EdgeTrust(point, (float(normal[0]), float(normal[1])), t_s)
    if (result.only_land or result.only_water) and recent:
        across_m = abs(float(np.subtract(own_en_m, trust.edge_en_m) @ np.asarray(trust.normal_en)))
        if across_m <= limits.in_view_fraction * result.footprint_side_m:
            return PerceptionResult.no_measurement(result.footprint_side_m), trust
    return result, trust


def _contradicts(point: tuple[float, float], normal: np.ndarray, t_s: float, trust: EdgeTrust,
                 limits: TrustLimits) -> bool:
    """Whether an edge seen at ``point`` with ``normal`` lies too far across, or runs too far turned from, the
    recent trusted edge for the time since it was seen."""
    age_s = max(t_s - trust.t_s, 0.0)
    trusted_normal = np.asarray(trust.normal_en)
    jump_m = abs(float(np.subtract(point, trust.edge_en_m) @ trusted_normal))
    if jump_m > limits.max_jump_m + limits.edge_speed_mps * age_s:
        return True
    cos_turn = float(normal @ trusted_normal) / max(float(np.hypot(normal[0], normal[1])), 1e-12)
    return cos_turn < math.cos(min(limits.max_turn_rad + limits.turn_rate_radps * age_s, math.pi))
