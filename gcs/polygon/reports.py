"""The ground station's caged polygon from the boundary drones' state messages (pure; both engines use it).

Each boundary drone's state message carries its position (odometry in the mission frame) and the water-edge points
its camera sees. The drones without GPS know positions only relative to their pads; the GPS leader reports both its
odometry position and its GPS fix, so the difference between the two is the offset that places the whole swarm's
odometry frame on the map. Each drone's reports of the last half second are fused
(:mod:`gcs.polygon.report_window`); the fusion itself is :func:`gcs.polygon.caged.caged_polygon`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from comms.frames import GeodeticHome, geodetic_to_enu
from comms.messages import FLAG_LEAVING, NeighbourState
from gcs.polygon.caged import caged_polygon
from gcs.polygon.report_window import ReportHistory, recent_points


def report_max_age_s(control_rate_hz: float) -> float:
    """How old a boundary drone's newest report may be before its ring slot counts as missing [s]: three control
    periods (the drones broadcast every period) plus a second for transport and a busy host."""
    return 3.0 / control_rate_hz + 1.0


def georeference_offset_en_m(leader: NeighbourState | None, home: GeodeticHome) -> NDArray[np.float64]:
    """GPS position minus odometry position of the GPS leader [m; E, N]; zero without a usable fix."""
    if leader is None or leader.lat_deg is None or leader.lon_deg is None:
        return np.zeros(2)
    gps_enu_m = geodetic_to_enu(leader.lat_deg, leader.lon_deg, home.alt_m, home)
    offset = np.asarray(gps_enu_m, dtype=float).reshape(-1)[:2] - np.asarray(leader.position_en_m, dtype=float)
    return offset if np.all(np.isfinite(offset)) else np.zeros(2)


def aggregate_polygon(
    states: Mapping[int, NeighbourState],
    ring_order: Sequence[int],
    offset_en_m: NDArray[np.float64],
    now_s: float,
    max_age_s: float,
    history: ReportHistory | None = None,
) -> NDArray[np.float64]:
    """The caged ring (K, 2) [m; mission E, N] from the boundary reports, georeferenced by ``offset_en_m``.

    Each drone's edge points are those of its reports in ``history`` over the last
    :data:`gcs.polygon.report_window.WINDOW_S` (its newest message's alone without a history). Boundary drones that
    left, or whose newest report is older than ``max_age_s``, count as missing (NaN row, no points): the ring closes
    over the gap. Returns an empty (0, 2) array while fewer than three points are known.
    """
    positions = np.full((len(ring_order), 2), np.nan)
    edge_points: list[NDArray[np.float64]] = []
    for row, vehicle_id in enumerate(ring_order):
        msg = states.get(vehicle_id)
        if msg is None or msg.has(FLAG_LEAVING) or now_s - msg.t_s > max_age_s:
            edge_points.append(np.zeros((0, 2)))
            continue
        positions[row] = np.asarray(msg.position_en_m, dtype=float) + offset_en_m
        if history is None:
            points = np.asarray(msg.edge_points_en_m, dtype=float).reshape(-1, 2)
        else:
            points = recent_points(history, vehicle_id, now_s)
        edge_points.append(points + offset_en_m)
    return caged_polygon(positions, edge_points)
