"""Where the mission is: the geodetic origin of the mission ENU frame (conversions live in ``comms.frames``)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class GeodeticHome:
    """Origin of the mission ENU frame [deg, deg, m AMSL]."""

    lat_deg: float = 47.397742
    lon_deg: float = 8.545594
    alt_m: float = 488.0
