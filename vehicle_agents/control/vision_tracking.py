"""Vision-based boundary tracking, eq 5, and the climb rule of Algorithm 1.

Eq 5: ``u_v = −K_b (q − p) + ṗ``. The drone needs no absolute position: ``p − q`` is the image offset of the
tracked point from the image centre, already in metres in :class:`PerceptionResult`.

Which point is p: the paper's p is the midpoint of the land and water centroids. For a straight edge that
midpoint sits half-way between the image centre and the edge, so the loop settles on the edge but with half the
gain; on a curved edge it is biased towards the concave side. The improved mode instead tracks the edge itself:
the median normal offset of the boundary pixels seen across the middle of the image.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from vehicle_agents.perception.result import PerceptionResult


def tracked_offset_en_m(perception: PerceptionResult, use_edge_points: bool) -> NDArray[np.float64] | None:
    """``p − q`` [m; E, N] for eq 5, or None when the image holds no edge (Algorithm 1, line 2)."""
    if not perception.has_edge or perception.midpoint_offset_en_m is None:
        return None
    midpoint = np.asarray(perception.midpoint_offset_en_m, dtype=float)
    if not use_edge_points or perception.edge_normal_en is None or perception.edge_tangent_en is None:
        return midpoint
    points = np.asarray(perception.edge_points_en_m, dtype=float).reshape(-1, 2)
    if points.shape[0] < 3:
        return midpoint
    n = np.asarray(perception.edge_normal_en, dtype=float)
    t = np.asarray(perception.edge_tangent_en, dtype=float)
    along = points @ t
    band = max(perception.footprint_side_m / 6.0, 0.5)
    near = points[np.abs(along) <= band]
    if near.shape[0] < 3:
        near = points
    return median(near @ n) * n


def median(values: NDArray[np.float64]) -> float:
    """``np.median`` of a non-empty 1-D array, bit for bit (the middle value, or the mean of the two middle ones;
    NaN if any is NaN), without its generic machinery, which costs more than sorting a few dozen numbers."""
    ordered = np.sort(values)
    if math.isnan(ordered[-1]):
        return math.nan
    middle = ordered.size // 2
    if ordered.size % 2:
        return float(ordered[middle])
    return (float(ordered[middle - 1]) + float(ordered[middle])) / 2.0


def tracking_velocity(
    offset_en_m: NDArray[np.float64], k_per_s: tuple[float, float], pdot_ff_en_mps: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Eq 5 with ``K_b = diag(k_east, k_north)``: ``K (p − q) + ṗ``."""
    return np.asarray(k_per_s, dtype=float) * np.asarray(offset_en_m, dtype=float) + pdot_ff_en_mps


def altitude_rate_mps(
    perception: PerceptionResult | None,
    altitude_m: float,
    nominal_altitude_m: float,
    climb_speed_mps: float,
    descent_speed_mps: float,
    k_altitude_per_s: float,
    max_altitude_m: float,
) -> tuple[float, bool]:
    """Algorithm 1's vertical rule: (climb rate [m/s, up positive], climbing?).

    Only land or only water in view: climb (the footprint grows) until both return, up to ``max_altitude_m``.
    Otherwise return gently to the nominal altitude (at most ``descent_speed_mps`` down). No usable image at all
    (``None`` or no measurement): hold the nominal altitude.
    """
    lost = perception is not None and (perception.only_land or perception.only_water)
    if lost:
        return (climb_speed_mps if altitude_m < max_altitude_m else 0.0), True
    error_m = nominal_altitude_m - altitude_m
    return float(np.clip(k_altitude_per_s * error_m, -descent_speed_mps, climb_speed_mps)), False
