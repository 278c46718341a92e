"""The caged flood polygon for the rescue centre (§III-B): aggregated from the boundary drones' state messages,
recorded, logged as GeoJSON lines, and published on ``<mission>/gcs/polygon`` as a georeferenced feature."""

from __future__ import annotations

import datetime as dt
import math
import time
from collections.abc import Collection, Mapping, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from comms.flood_polygon import flood_polygon_from_enu
from comms.frames import GeodeticHome
from comms.keys import MissionKeys
from comms.messages import NeighbourState, encode
from comms.zenoh_session import ZenohSession
from gcs.mission_record import PolygonSample
from gcs.polygon.growth import polygon_growth_rate_m2ps
from gcs.polygon.report_window import NO_REPORTS, ReportHistory, remembered
from gcs.polygon.reports import aggregate_polygon, georeference_offset_en_m, report_max_age_s
from gcs.report.polygon_log import PolygonLog


class PolygonPublisher:
    """Builds the caged polygon from the boundary drones' recent state messages and hands it to the recorder, the
    log and Zenoh."""

    def __init__(self, keys: MissionKeys, mission: str, home: GeodeticHome, ring_order: Sequence[int],
                 leader_id: int | None, control_rate_hz: float, polygons: list[PolygonSample]) -> None:
        self.keys, self.mission, self.home = keys, mission, home
        self.ring_order = list(ring_order)
        self.leader_id = leader_id
        self.max_age_s = report_max_age_s(control_rate_hz)
        self.polygons = polygons
        self.log: PolygonLog | None = None
        self.area_m2 = math.nan
        self.history: ReportHistory = NO_REPORTS

    def remember(self, states: Mapping[int, NeighbourState], mission_t_s: float) -> None:
        """Keep the boundary drones' newest reports (called at every poll; the polygon fuses the last half second)."""
        self.history = remembered(self.history, states, self.ring_order, mission_t_s)

    def start_log(self, out_dir: Path, start_utc: dt.datetime) -> None:
        """Open the polygon log (GeoJSON lines) at flood time 0."""
        self.log = PolygonLog(out_dir, self.home, start_utc=start_utc)

    def close(self) -> None:
        if self.log is not None:
            self.log.close()

    def publish(self, hub: ZenohSession, states: Mapping[int, NeighbourState], lost: Collection[int],
                mission_t_s: float, flood_t_s: float) -> NDArray[np.float64]:
        """Aggregate, record, log and publish the polygon; returns the ring [m; mission EN] (empty if < 3 points)."""
        leader = states.get(self.leader_id) if self.leader_id is not None else None
        offset = georeference_offset_en_m(leader, self.home)
        ring = aggregate_polygon(states, self.ring_order, offset, mission_t_s, self.max_age_s, self.history)
        if len(ring) < 3:
            return ring
        self.polygons.append(PolygonSample(t_s=flood_t_s, ring_en_m=ring))
        if self.log is not None:
            self.log.append(flood_t_s, ring)
        try:
            feature = flood_polygon_from_enu(
                ring, self.home, mission=self.mission, t_s=flood_t_s,
                growth_rate_m2_per_s=polygon_growth_rate_m2ps(self.polygons),
                vehicle_ids=[vid for vid in self.ring_order if vid in states and vid not in lost],
                utc_iso=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            )
        except ValueError:
            return ring
        hub.put(self.keys.polygon, encode(feature))
        self.area_m2 = feature.properties.area_m2
        return ring
