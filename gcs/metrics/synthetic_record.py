"""A scripted, ideal ``circle`` mission as a MissionRecord: known answers for tests, benchmarks and report previews.

No control law runs here. Boundary drones leave the launch point (angle 0) in two groups and spread evenly round
the expanding circle over ``spread_s`` seconds, riding the edge; the leader sits at the centre; followers sit
``follower_radius_m`` out at 45° + k·90° (more than four fill the disc of that radius on a Vogel spiral). The ground station polygon at each ``polygon_period_s`` is built with
:func:`gcs.polygon.caged_polygon` from the drones and the true edge points inside each boundary footprint.
Optionally one boundary drone is lost at ``loss_at_s`` and the others re-space over ``respace_s``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from gcs.metrics.coverage import footprint_side_m
from gcs.mission_record import MissionRecord, PolygonSample
from gcs.polygon.caged import caged_polygon
from mission_plan.roles import Role
from mock_autopilot.world.flood_model import ExpandingCircle


def synthetic_circle_record(
    *,
    n_boundary: int = 8,
    n_followers: int = 4,
    duration_s: float = 60.0,
    rate_hz: float = 10.0,
    altitude_m: float = 10.0,
    fov_deg: float = 60.0,
    spread_s: float = 20.0,
    follower_radius_m: float = 8.0,
    polygon_period_s: float = 0.5,
    edge_noise_m: float = 0.05,
    loss_at_s: float | None = None,
    respace_s: float = 5.0,
    flood: ExpandingCircle | None = None,
    seed: int = 0,
) -> tuple[MissionRecord, ExpandingCircle]:
    """The record of an ideal run on ``flood`` (the paper's 12 m -> 16 m circle by default) and that flood."""
    flood = flood or ExpandingCircle()
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(duration_s * rate_hz)) + 1) / rate_hz
    n_v = 1 + n_followers + n_boundary
    roles = [Role.LEADER] + [Role.FOLLOWER] * n_followers + [Role.BOUNDARY] * n_boundary
    pos = np.zeros((len(t), n_v, 3))
    alive = np.ones((len(t), n_v), bool)
    cx, cy = flood.center_en_m
    lost = n_v - 1 if loss_at_s is not None else None

    for k, tk in enumerate(t):
        r = flood.radius_m(float(tk))
        pos[k, 0] = (cx, cy, altitude_m)
        for j, (fx, fy) in enumerate(_follower_offsets(n_followers, follower_radius_m)):
            pos[k, 1 + j] = (cx + fx, cy + fy, altitude_m)
        angles = _boundary_angles(n_boundary, float(tk), spread_s, loss_at_s, respace_s)
        for b, a in enumerate(angles):
            pos[k, 1 + n_followers + b] = (cx + r * math.cos(a), cy + r * math.sin(a), altitude_m)
        if lost is not None and loss_at_s is not None and tk >= loss_at_s:
            alive[k, lost] = False

    sides = np.where(alive, footprint_side_m(pos[..., 2], fov_deg), 0.0)
    boundary = np.arange(1 + n_followers, n_v)
    polygons = _polygons(flood, t, pos, alive, sides, boundary, polygon_period_s, edge_noise_m, rng)

    record = MissionRecord(
        scenario="circle",
        mode="synthetic",
        engine="synthetic",
        seed=seed,
        vehicle_ids=list(range(1, n_v + 1)),
        roles=roles,
        t_s=t,
        positions_enu_m=pos,
        commands_enu_mps=np.zeros_like(pos),
        footprint_side_m=sides,
        alive=alive,
        polygons=polygons,
        encircle_time_s=None,
        climb_events=[0] * n_v,
    )
    return record, flood


def _polygons(flood: ExpandingCircle, t: NDArray[np.float64], pos: NDArray[np.float64], alive: NDArray[np.bool_],
              sides: NDArray[np.float64], boundary: NDArray[np.int_], period_s: float, edge_noise_m: float,
              rng: np.random.Generator) -> list[PolygonSample]:
    """The caged polygon every ``period_s`` from what the live boundary drones' footprints see of the edge."""
    polygons = []
    next_poly = 0.0
    for k, tk in enumerate(t):
        if tk + 1e-9 < next_poly:
            continue
        next_poly += period_s
        live = boundary[alive[k, boundary]]
        edges = [_visible_edge(flood, float(tk), pos[k, i, :2], sides[k, i], edge_noise_m, rng) for i in live]
        polygons.append(PolygonSample(float(tk), caged_polygon(pos[k, live, :2], edges)))
    return polygons


def _follower_offsets(n: int, radius_m: float) -> NDArray[np.float64]:
    """Up to 4 followers at ``radius_m`` on the diagonals (the layout of the paper's Fig. 8); more fill a disc (Vogel spiral)."""
    if n <= 4:
        a = math.pi / 4 + np.arange(n) * math.pi / 2
        return np.stack([radius_m * np.cos(a), radius_m * np.sin(a)], axis=-1)
    k = np.arange(1, n + 1)
    r = radius_m * np.sqrt(k / n)
    a = k * math.pi * (3.0 - math.sqrt(5.0))
    return np.stack([r * np.cos(a), r * np.sin(a)], axis=-1)


def _boundary_angles(n: int, t_s: float, spread_s: float, loss_at_s: float | None, respace_s: float) -> NDArray[np.float64]:
    """Ring angles: two groups fan out from angle 0 in opposite directions, then (after a loss) re-space."""
    frac = min(1.0, t_s / spread_s) if spread_s > 0 else 1.0
    k = np.arange(n)
    signed = np.where(k % 2 == 0, 1.0, -1.0) * ((k // 2) + 0.5)
    start_gap_rad = 0.125  # ~2 m of arc at the launch: the pads are not stacked
    angles = signed * (start_gap_rad + (2 * math.pi / n - start_gap_rad) * frac)
    if loss_at_s is not None and t_s >= loss_at_s:
        survivors = n - 1
        target = np.sort(np.mod(angles[:survivors], 2 * math.pi))
        even = target[0] + np.arange(survivors) * 2 * math.pi / survivors
        blend = min(1.0, (t_s - loss_at_s) / respace_s) if respace_s > 0 else 1.0
        order = np.argsort(np.mod(angles[:survivors], 2 * math.pi))
        moved = angles.copy()
        moved[order] = target + blend * (even - target)
        angles = moved
    return angles


def _visible_edge(
    flood: ExpandingCircle, t_s: float, centre_en_m: NDArray[np.float64], side_m: float, noise_m: float, rng: np.random.Generator
) -> NDArray[np.float64]:
    """True edge points inside one axis-aligned footprint, every ~0.1 m, with Gaussian noise."""
    r = flood.radius_m(t_s)
    theta = np.linspace(0.0, 2 * math.pi, max(64, int(2 * math.pi * r / 0.1)), endpoint=False)
    ring = np.stack([flood.center_en_m[0] + r * np.cos(theta), flood.center_en_m[1] + r * np.sin(theta)], axis=-1)
    inside = np.all(np.abs(ring - centre_en_m) <= side_m / 2, axis=1)
    pts = ring[inside]
    return pts + rng.normal(0.0, noise_m, pts.shape)
