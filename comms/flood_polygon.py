"""The caged flood polygon for the rescue centre as a GeoJSON Feature (RFC 7946: WGS84 ``[lon, lat]``,
counter-clockwise outer ring), encoded as UTF-8 JSON so that it can be used without our code; its version is
``properties.schema``."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Literal

import msgspec
import numpy as np
from numpy.typing import ArrayLike

from comms.frames import GeodeticHome, enu_to_geodetic
from comms.message_checks import InvalidMessage, Point2, finite_points
from mission_plan.geometry import signed_area_m2


class GeoJsonPolygon(msgspec.Struct, frozen=True, tag_field="type", tag="Polygon"):
    """RFC 7946 Polygon geometry: rings of ``[lon, lat]`` positions, first = last, outer ring counter-clockwise."""

    coordinates: list[list[Point2]]


class FloodPolygonProperties(msgspec.Struct, frozen=True, omit_defaults=True):
    """What the rescue centre needs next to the shape; ``schema`` carries the version."""

    schema: Literal["fw/polygon/1"]
    mission: str
    t_s: float
    area_m2: float
    perimeter_m: float
    growth_rate_m2_per_s: float | None = None  # null until two polygons exist (JSON has no NaN)
    vehicle_ids: list[int] = []
    utc_iso: str = ""


class FloodPolygon(msgspec.Struct, frozen=True, tag_field="type", tag="Feature"):
    """The ground station's caged flood polygon as a GeoJSON Feature (public key ``.../gcs/polygon``)."""

    geometry: GeoJsonPolygon
    properties: FloodPolygonProperties

    def __post_init__(self) -> None:
        rings = self.geometry.coordinates
        if not rings or len(rings[0]) < 4 or not all(finite_points(r) for r in rings):
            raise InvalidMessage("polygon needs a closed finite outer ring of >= 4 positions")


def flood_polygon_from_enu(
    ring_en_m: ArrayLike,
    home: GeodeticHome,
    *,
    mission: str,
    t_s: float,
    growth_rate_m2_per_s: float | None = None,
    vehicle_ids: Sequence[int] = (),
    utc_iso: str = "",
) -> FloodPolygon:
    """Build the GeoJSON polygon from a mission-ENU ring (K, 2): closes it, makes it counter-clockwise (RFC 7946),
    converts to ``[lon, lat]`` through ``comms.frames``, and fills area and perimeter [m², m] from the ENU ring.

    A non-finite growth rate (e.g. NaN before two polygons exist) becomes null; a non-finite ring or time, or fewer
    than 3 distinct vertices, raises ValueError (JSON cannot carry NaN, and the receiver would drop it)."""
    ring = np.asarray(ring_en_m, dtype=float).reshape(-1, 2)
    if not (np.isfinite(ring).all() and math.isfinite(t_s)):
        raise ValueError("polygon ring and t_s must be finite")
    if len(ring) >= 2 and np.allclose(ring[0], ring[-1]):
        ring = ring[:-1]
    if len(ring) < 3:
        raise ValueError("a polygon needs at least 3 distinct vertices")
    signed_area = signed_area_m2(ring)
    if signed_area < 0:
        ring = ring[::-1]
    perimeter_m = float(np.sum(np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)))
    geo = enu_to_geodetic(ring, home)
    coords = [(float(lon), float(lat)) for lat, lon in geo[:, :2]]
    coords.append(coords[0])
    return FloodPolygon(
        geometry=GeoJsonPolygon(coordinates=[coords]),
        properties=FloodPolygonProperties(
            schema="fw/polygon/1",
            mission=mission,
            t_s=float(t_s),
            area_m2=abs(signed_area),
            perimeter_m=perimeter_m,
            growth_rate_m2_per_s=(
                float(growth_rate_m2_per_s)
                if growth_rate_m2_per_s is not None and math.isfinite(growth_rate_m2_per_s)
                else None
            ),
            vehicle_ids=[int(v) for v in vehicle_ids],
            utc_iso=utc_iso,
        ),
    )
