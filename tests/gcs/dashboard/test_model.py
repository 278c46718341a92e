"""The page's model: ages of values, alerts raised and cleared, polygon history."""

from __future__ import annotations

from comms.frames import GeodeticHome
from comms.gcs_status import EventKind, LinkState, MissionEvent, VehicleStatus, VehicleStatusReport
from comms.messages import flood_polygon_from_enu
from gcs.dashboard.model import DashboardModel

HOME = GeodeticHome(lat_deg=47.0, lon_deg=8.0, alt_m=400.0)


def _report(wall_s: float) -> VehicleStatusReport:
    row = VehicleStatus(vehicle_id=1, role="boundary", link=LinkState.OK, agent_alive=True, heartbeat_age_s=0.2,
                        state_age_s=0.1, lat_deg=47.0, lon_deg=8.0)
    return VehicleStatusReport(t_s=10.0, wall_s=wall_s, phase="mission", vehicles=[row], flood_t_s=3.0)


def _event(seq: int, kind: EventKind, vehicle: int | None, active: bool = True) -> MissionEvent:
    return MissionEvent(seq=seq, t_s=seq, wall_s=100.0 + seq, kind=kind, text=f"event {seq}", vehicle_id=vehicle,
                        active=active)


def test_ages_grow_with_the_time_since_the_report_was_published() -> None:
    model = DashboardModel("m")
    model.on_vehicles(_report(100.0), now_wall_s=100.05)
    frame = model.frame(now_wall_s=103.0)
    row = frame["vehicles"][0]
    assert frame["report_age_s"] == 3.0
    assert abs(row["heartbeat_age_s"] - 3.2) < 1e-9 and abs(row["state_age_s"] - 3.1) < 1e-9


def test_alerts_stand_until_cleared_and_events_are_kept_once() -> None:
    model = DashboardModel("m")
    model.on_event(_event(1, EventKind.AGENT_LOST, 5), 150.0)
    model.on_event(_event(1, EventKind.AGENT_LOST, 5), 150.0)
    model.on_event(_event(2, EventKind.INFO, None), 150.0)
    model.on_event(_event(3, EventKind.VEHICLE_LOST, 6), 150.0)
    frame = model.frame(200.0)
    assert len(frame["events"]) == 3
    assert {(a["kind"], a["vehicle_id"]) for a in frame["alerts"]} == {("agent_lost", 5), ("vehicle_lost", 6)}
    model.on_event(_event(4, EventKind.VEHICLE_LOST, 6, active=False), 150.0)
    assert [(a["kind"], a["vehicle_id"]) for a in model.frame(200.0)["alerts"]] == [("agent_lost", 5)]


def test_history_serves_polygons_from_an_index_and_a_restarted_flood_clock_starts_it_again() -> None:
    model = DashboardModel("m")
    for t in range(5):
        ring = [(0.0, 0.0), (10.0 + t, 0.0), (10.0 + t, 10.0), (0.0, 10.0)]
        model.on_polygon(flood_polygon_from_enu(ring, HOME, mission="m", t_s=float(t)), now_wall_s=100.0 + t)
    history = model.history(3)
    assert history["count"] == 5 and [i["t_s"] for i in history["items"]] == [3.0, 4.0]
    assert history["items"][0]["area_m2"] == 130.0 and len(history["items"][0]["ring"]) == 5
    model.on_polygon(flood_polygon_from_enu([(0, 0), (5, 0), (5, 5)], HOME, mission="m", t_s=0.0), now_wall_s=200.0)
    assert model.history(0)["count"] == 1


def test_a_partial_frame_leaves_out_what_did_not_change_lately() -> None:
    model = DashboardModel("m")
    model.on_polygon(flood_polygon_from_enu([(0, 0), (5, 0), (5, 5)], HOME, mission="m", t_s=1.0), now_wall_s=100.0)
    model.on_event(_event(1, EventKind.INFO, None), now_wall_s=100.0)
    assert {"polygon", "events", "alerts"} <= model.frame(100.2, full=False).keys()
    late = model.frame(102.0, full=False)
    assert not {"polygon", "events", "alerts", "flood_edge"} & late.keys() and late["polygon_count"] == 1
    assert model.frame(102.0)["polygon"]["properties"]["t_s"] == 1.0
