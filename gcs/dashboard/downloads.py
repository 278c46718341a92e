"""The current caged polygon as files a rescue centre opens directly: GeoJSON (RFC 7946) and KML 2.2 (pure)."""

from __future__ import annotations

from xml.sax.saxutils import escape

from comms.messages import FloodPolygon, encode
from gcs.report.kml import KML_FOOTER, STYLE_ID, kml_header


def polygon_geojson(feature: FloodPolygon) -> bytes:
    """The Feature exactly as the ground station published it (UTF-8 JSON)."""
    return encode(feature)


def polygon_kml(feature: FloodPolygon) -> str:
    """One Placemark with the polygon, clamped to the ground, named by its flood time and area."""
    props = feature.properties
    tuples = " ".join(f"{lon:.8f},{lat:.8f},0" for lon, lat in feature.geometry.coordinates[0])
    when = f"<TimeStamp><when>{escape(props.utc_iso)}</when></TimeStamp>" if props.utc_iso else ""
    placemark = (
        "<Placemark>"
        f"<name>{escape(props.mission)}: flood t = {props.t_s:.1f} s</name>"
        f"<description>area {props.area_m2:.1f} m2, perimeter {props.perimeter_m:.1f} m</description>"
        f"{when}<styleUrl>#{STYLE_ID}</styleUrl>"
        "<Polygon><altitudeMode>clampToGround</altitudeMode><outerBoundaryIs><LinearRing>"
        f"<coordinates>{tuples}</coordinates>"
        "</LinearRing></outerBoundaryIs></Polygon>"
        "</Placemark>\n"
    )
    return kml_header(f"FloodWatch {props.mission}: caged flood polygon") + placemark + KML_FOOTER
