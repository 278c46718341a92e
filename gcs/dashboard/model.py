"""What the page shows, accumulated from the mission's messages (pure: the feed hands it decoded messages and the
wall time; no sockets, no clocks).

One frame (:meth:`DashboardModel.frame`) is everything the page redraws: vehicles with the age of every value, the
newest caged polygon, the true flood edge, the newest events and the alerts standing. The polygon history (for the
time slider and the area chart) is fetched separately, by index, so the frame stays small however long the run.
"""

from __future__ import annotations

import collections
import math
from dataclasses import dataclass
from typing import Any

import msgspec

from comms.gcs_status import ALERT_KINDS, FloodEdgeTruth, MissionEvent, VehicleStatusReport
from comms.messages import FloodPolygon

RESEND_S = 0.3
"""A frame carries the polygon, the true edge and the events only within this long [s] of their last change (and in
full frames): they change about once a second, the frames come ten or more times a second, so a change still
reaches a page that skipped a frame or two."""
MAX_EVENTS = 200
MAX_POLYGONS = 20_000
"""About five and a half hours of polygons at the default 1 Hz; the oldest go first beyond it."""


@dataclass(frozen=True)
class PolygonEntry:
    """One caged polygon as received: the GeoJSON Feature and the wall time it arrived."""

    feature: FloodPolygon
    received_wall_s: float


class DashboardModel:
    """The newest of everything, the polygons seen so far, and the standing alerts."""

    def __init__(self, mission: str) -> None:
        self.mission = mission
        self.vehicles: VehicleStatusReport | None = None
        self.vehicles_received_wall_s = 0.0
        self.flood_edge: FloodEdgeTruth | None = None
        self.polygons: collections.deque[PolygonEntry] = collections.deque(maxlen=MAX_POLYGONS)
        self.polygons_dropped = 0
        self.events: collections.deque[MissionEvent] = collections.deque(maxlen=MAX_EVENTS)
        self.alerts: dict[tuple[str, int | None], MissionEvent] = {}
        self._changed_wall_s: dict[str, float] = {}

    # ---- inputs
    def on_vehicles(self, report: VehicleStatusReport, now_wall_s: float) -> None:
        if self.vehicles is None or report.t_s >= self.vehicles.t_s or report.wall_s > self.vehicles.wall_s:
            self.vehicles = report
            self.vehicles_received_wall_s = now_wall_s

    def on_polygon(self, feature: FloodPolygon, now_wall_s: float) -> None:
        if self.polygons and feature.properties.t_s < self.polygons[-1].feature.properties.t_s:
            self.polygons.clear()  # a new run under the same mission name started its flood clock again
        if len(self.polygons) == self.polygons.maxlen:
            self.polygons_dropped += 1
        self.polygons.append(PolygonEntry(feature, now_wall_s))
        self._changed_wall_s["polygon"] = now_wall_s

    def on_flood_edge(self, edge: FloodEdgeTruth, now_wall_s: float) -> None:
        self.flood_edge = edge
        self._changed_wall_s["flood_edge"] = now_wall_s

    def on_event(self, event: MissionEvent, now_wall_s: float) -> None:
        if any(e.seq == event.seq and e.wall_s == event.wall_s for e in self.events):
            return
        self.events.append(event)
        self._changed_wall_s["events"] = now_wall_s
        if event.kind in ALERT_KINDS:
            key = (event.kind.value, event.vehicle_id)
            if event.active:
                self.alerts[key] = event
            else:
                self.alerts.pop(key, None)

    # ---- outputs
    @property
    def current_polygon(self) -> FloodPolygon | None:
        return self.polygons[-1].feature if self.polygons else None

    def frame(self, now_wall_s: float, full: bool = True) -> dict[str, Any]:
        """The page's state now. Ages [s] are at ``now_wall_s``: a report's values aged by the time since it was
        published (``wall_s``, the publisher's clock) — equal clocks on one machine, and on two machines the
        receive time bounds it from below. A frame that is not ``full`` leaves out the polygon, the true edge and
        the events (with the alerts) unless they changed within :data:`RESEND_S`; the page keeps what it has."""
        report = self.vehicles
        vehicles: list[dict[str, Any]] = []
        report_age_s = None
        if report is not None:
            report_age_s = max(0.0, now_wall_s - min(report.wall_s, self.vehicles_received_wall_s))
            for v in report.vehicles:
                row = msgspec.to_builtins(v)
                row["heartbeat_age_s"] = None if v.heartbeat_age_s is None else v.heartbeat_age_s + report_age_s
                row["state_age_s"] = None if v.state_age_s is None else v.state_age_s + report_age_s
                vehicles.append(row)
        polygon = self.current_polygon
        newest = self.polygons[-1] if self.polygons else None
        frame: dict[str, Any] = {
            "mission": self.mission,
            "now_wall_s": now_wall_s,
            "phase": report.phase if report else "waiting",
            "t_s": report.t_s if report else None,
            "flood_t_s": report.flood_t_s if report else None,
            "report_wall_s": report.wall_s if report else None,
            "report_age_s": report_age_s,
            "operator_order": report.operator_order if report else "",
            "home": [report.home_lat_deg, report.home_lon_deg] if report and report.home_lat_deg is not None else None,
            "vehicles": vehicles,
            "polygon_age_s": now_wall_s - newest.received_wall_s if newest else None,
            "polygon_count": len(self.polygons),
        }
        fresh = [part for part in ("polygon", "flood_edge", "events")
                 if full or now_wall_s - self._changed_wall_s.get(part, -math.inf) <= RESEND_S]
        if "polygon" in fresh:
            frame["polygon"] = msgspec.to_builtins(polygon) if polygon else None
        if "flood_edge" in fresh:
            frame["flood_edge"] = msgspec.to_builtins(self.flood_edge) if self.flood_edge else None
        if "events" in fresh:
            frame["events"] = [msgspec.to_builtins(e) for e in list(self.events)[-30:]]
            frame["alerts"] = [msgspec.to_builtins(e) for e in self.alerts.values()]
        return frame

    def history(self, start: int) -> dict[str, Any]:
        """Polygons from index ``start`` on (index into what is kept): rings for the slider, area and growth for
        the chart."""
        entries = list(self.polygons)[max(0, start):]
        return {
            "start": max(0, start),
            "count": len(self.polygons),
            "items": [{
                "t_s": e.feature.properties.t_s,
                "area_m2": e.feature.properties.area_m2,
                "growth_rate_m2_per_s": e.feature.properties.growth_rate_m2_per_s,
                "ring": e.feature.geometry.coordinates[0],
            } for e in entries],
        }
