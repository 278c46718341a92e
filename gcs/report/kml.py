"""The caged polygon time series as KML 2.2: one Placemark per sample with a TimeStamp, for Google Earth's slider.

KML wants ``lon,lat[,alt]`` tuples and closed outer rings; the ring is drawn clamped to the ground. Placemarks are
plain strings so the incremental log can append them one by one.
"""

from __future__ import annotations

from datetime import datetime
from xml.sax.saxutils import escape

from numpy.typing import ArrayLike

from comms.frames import GeodeticHome
from gcs.polygon.ring import ring_area_m2
from gcs.report.geojson import ring_to_lonlat, utc_iso

KML_NAMESPACE = "http://www.opengis.net/kml/2.2"
STYLE_ID = "caged"


def kml_header(document_name: str) -> str:
    """Everything before the first Placemark, with one polygon style (translucent blue fill, dark blue outline)."""
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<kml xmlns="{KML_NAMESPACE}">\n'
        "<Document>\n"
        f"<name>{escape(document_name)}</name>\n"
        f'<Style id="{STYLE_ID}"><LineStyle><color>ff8b3d00</color><width>2</width></LineStyle>'
        "<PolyStyle><color>66ff9933</color></PolyStyle></Style>\n"
    )


KML_FOOTER = "</Document>\n</kml>\n"


def kml_placemark(ring_en_m: ArrayLike, t_s: float, home: GeodeticHome, start_utc: datetime, name: str = "") -> str:
    """One Placemark (Polygon + TimeStamp) for a ring, or "" when the ring has < 3 vertices."""
    coordinates = ring_to_lonlat(ring_en_m, home)
    if not coordinates:
        return ""
    tuples = " ".join(f"{lon:.8f},{lat:.8f},0" for lon, lat in coordinates)
    label = name or f"t = {t_s:.1f} s"
    return (
        "<Placemark>"
        f"<name>{escape(label)}</name>"
        f"<description>area {ring_area_m2(ring_en_m):.1f} m2</description>"
        f"<TimeStamp><when>{utc_iso(start_utc, t_s)}</when></TimeStamp>"
        f"<styleUrl>#{STYLE_ID}</styleUrl>"
        "<Polygon><altitudeMode>clampToGround</altitudeMode><outerBoundaryIs><LinearRing>"
        f"<coordinates>{tuples}</coordinates>"
        "</LinearRing></outerBoundaryIs></Polygon>"
        "</Placemark>\n"
    )
