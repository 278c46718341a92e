"""The ground station's pure parts: georeferencing through the GPS leader, polygon aggregation, the live view."""

from __future__ import annotations

import math

import numpy as np
from rich.console import Console

from comms.frames import GeodeticHome, enu_to_geodetic
from comms.messages import FLAG_LEAVING, NeighbourState
from gcs.metrics.polygon_quality import polygon_iou
from gcs.processes.live_view import MissionSnapshot, VehicleRow, render, status_line
from gcs.polygon.reports import aggregate_polygon, georeference_offset_en_m

HOME = GeodeticHome()


def _boundary(vid: int, angle: float, radius: float = 12.0, t_s: float = 10.0, flags: int = 0,
              shift: tuple[float, float] = (0.0, 0.0)) -> NeighbourState:
    """A boundary drone on a circle seeing an arc of the edge around it (positions shifted like drifted odometry)."""
    pos = (radius * math.cos(angle) + shift[0], radius * math.sin(angle) + shift[1])
    arc = np.linspace(angle - 0.4, angle + 0.4, 20)
    edge = [(radius * math.cos(a) + shift[0], radius * math.sin(a) + shift[1]) for a in arc]
    return NeighbourState(sender_id=vid, role="boundary", seq=1, t_s=t_s, position_en_m=pos, altitude_m=10.0,
                          flags=flags, edge_points_en_m=edge)


def test_offset_is_gps_minus_odometry_of_the_leader() -> None:
    lat, lon, _ = enu_to_geodetic(np.array([3.0, -2.0, 0.0]), HOME)
    leader = NeighbourState(sender_id=9, role="leader", seq=1, t_s=1.0, position_en_m=(1.0, 1.0), altitude_m=10.0,
                            lat_deg=float(lat), lon_deg=float(lon))
    np.testing.assert_allclose(georeference_offset_en_m(leader, HOME), [2.0, -3.0], atol=1e-6)
    no_fix = NeighbourState(sender_id=9, role="leader", seq=1, t_s=1.0, position_en_m=(1.0, 1.0), altitude_m=10.0)
    np.testing.assert_allclose(georeference_offset_en_m(no_fix, HOME), [0.0, 0.0])
    np.testing.assert_allclose(georeference_offset_en_m(None, HOME), [0.0, 0.0])


def test_aggregate_polygon_fuses_edge_points_and_applies_offset() -> None:
    shift = (0.5, -0.5)
    order = list(range(1, 9))
    states = {vid: _boundary(vid, 2 * math.pi * (vid - 1) / 8, shift=shift) for vid in order}
    truth = np.stack([12.0 * np.cos(np.linspace(0, 2 * math.pi, 256, endpoint=False)),
                      12.0 * np.sin(np.linspace(0, 2 * math.pi, 256, endpoint=False))], axis=1)
    ring = aggregate_polygon(states, order, -np.array(shift), now_s=10.0, max_age_s=1.0)
    assert polygon_iou(ring, truth) > 0.97
    uncorrected = aggregate_polygon(states, order, np.zeros(2), now_s=10.0, max_age_s=1.0)
    assert polygon_iou(uncorrected, truth) < polygon_iou(ring, truth)


def test_stale_and_leaving_drones_are_missing_not_wrong() -> None:
    order = list(range(1, 9))
    states = {vid: _boundary(vid, 2 * math.pi * (vid - 1) / 8) for vid in order}
    states[3] = _boundary(3, 2 * math.pi * 2 / 8, radius=30.0, t_s=2.0)  # an old report far away
    states[5] = _boundary(5, 2 * math.pi * 4 / 8, radius=30.0, flags=FLAG_LEAVING)
    ring = aggregate_polygon(states, order, np.zeros(2), now_s=10.0, max_age_s=1.0)
    assert np.max(np.hypot(ring[:, 0], ring[:, 1])) < 13.0
    assert len(aggregate_polygon({}, order, np.zeros(2), now_s=10.0, max_age_s=1.0)) == 0


def test_live_view_renders_every_vehicle_and_the_numbers() -> None:
    rows = tuple(
        VehicleRow(vehicle_id=i, role="boundary", group="A", mode="OFFBOARD", armed=True, altitude_m=10.0,
                   heartbeat_age_s=0.2 if i != 3 else 5.0, agent_alive=i != 2, state_age_s=0.1, battery_fraction=0.9,
                   sees_edge=True)
        for i in range(1, 5)
    )
    snap = MissionSnapshot(scenario="circle", mode="improved", phase="mission", mission_t_s=40.0, flood_t_s=25.0,
                           duration_s=60.0, speed=2.0, vehicles=rows, encircled=2, boundary_count=8,
                           polygon_iou=0.981, coverage=0.93, polygon_area_m2=600.0, events=("agent 2 lost",))
    console = Console(record=True, width=140)
    console.print(render(snap))
    text = console.export_text()
    assert "phase mission" in text and "0.981" in text and "0.930" in text
    assert "agent gone" in text and "vehicle lost" in text and "agent 2 lost" in text
    assert "IoU=0.981" in status_line(snap)
