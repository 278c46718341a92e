"""The caged polygon as GeoJSON (RFC 7946): WGS84 ``[lon, lat]`` positions, closed counter-clockwise outer rings.

Mission ENU rings are converted through ``comms.frames.enu_to_geodetic`` (the one frame module). East maps to
increasing longitude and north to increasing latitude, so a counter-clockwise ENU ring stays counter-clockwise in
``[lon, lat]``; the functions here still re-orient to be safe. Coordinates carry 8 decimals (≈ 1 mm), enough for
a round trip back to ENU within a centimetre (RFC 7946 §11.2 suggests 6 for display; we keep measurement precision).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from datetime import datetime, timedelta
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from comms.frames import GeodeticHome, enu_to_geodetic, geodetic_to_enu
from gcs.polygon.ring import open_ring, orient_ccw, ring_area_m2, ring_perimeter_m, signed_area_m2

COORDINATE_DECIMALS = 8


def utc_iso(start_utc: datetime, t_s: float) -> str:
    """ISO 8601 UTC timestamp of flood time ``t_s`` for a flood clock that started at ``start_utc``."""
    moment = start_utc + timedelta(seconds=float(t_s))
    return moment.strftime("%Y-%m-%dT%H:%M:%S.") + f"{moment.microsecond // 1000:03d}Z"


def ring_to_lonlat(ring_en_m: ArrayLike, home: GeodeticHome) -> list[list[float]]:
    """A (K, 2) ENU ring -> closed CCW list of ``[lon, lat]`` (K + 1 positions); empty if fewer than 3 vertices."""
    ring = open_ring(ring_en_m)
    ring = ring[np.all(np.isfinite(ring), axis=1)]
    if len(ring) < 3:
        return []
    geo = enu_to_geodetic(orient_ccw(ring), home)
    lonlat = np.round(np.stack([geo[:, 1], geo[:, 0]], axis=-1), COORDINATE_DECIMALS)
    if signed_area_m2(lonlat) < 0.0:
        lonlat = lonlat[::-1]
    closed = np.vstack([lonlat, lonlat[:1]])
    return [[float(lon), float(lat)] for lon, lat in closed]


def lonlat_to_ring(coordinates: Sequence[Sequence[float]], home: GeodeticHome) -> NDArray[np.float64]:
    """A GeoJSON linear ring (closed ``[lon, lat]`` list) -> open (K, 2) mission ENU ring."""
    arr = np.asarray(coordinates, dtype=float).reshape(-1, 2 if len(coordinates[0]) == 2 else 3)
    enu = geodetic_to_enu(arr[:, 1], arr[:, 0], home.alt_m, home)
    return open_ring(enu[:, :2])


def polygon_feature(
    ring_en_m: ArrayLike,
    t_s: float,
    home: GeodeticHome,
    start_utc: datetime,
    properties: Mapping[str, Any] | None = None,
) -> dict[str, Any] | None:
    """One time sample of the caged polygon as a GeoJSON Feature, or None when the ring has < 3 vertices.

    Properties: ``t_s`` (flood clock), ``time`` (ISO 8601 UTC), ``area_m2``, ``perimeter_m``, plus ``properties``.
    """
    coordinates = ring_to_lonlat(ring_en_m, home)
    if not coordinates:
        return None
    props: dict[str, Any] = {
        "t_s": round(float(t_s), 3),
        "time": utc_iso(start_utc, t_s),
        "area_m2": round(ring_area_m2(ring_en_m), 3),
        "perimeter_m": round(ring_perimeter_m(ring_en_m), 3),
    }
    for key, value in (properties or {}).items():
        props[key] = None if isinstance(value, float) and not math.isfinite(value) else value
    return {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [coordinates]}, "properties": props}


def feature_collection(features: Sequence[Mapping[str, Any]], properties: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """A FeatureCollection of the given features (foreign member ``properties`` only when given)."""
    collection: dict[str, Any] = {"type": "FeatureCollection", "features": list(features)}
    if properties:
        collection["properties"] = dict(properties)
    return collection
