"""Mission outputs of SPEC §6: metrics.json, GeoJSON/KML polygon time series, the Fig. 8 plot and an animation."""

from gcs.report.animation import write_animation
from gcs.report.geojson import feature_collection, lonlat_to_ring, polygon_feature, ring_to_lonlat, utc_iso
from gcs.report.kml import kml_header, kml_placemark
from gcs.report.outputs import write_metrics_json, write_mission_outputs, write_polygon_files
from gcs.report.polygon_log import PolygonLog
from gcs.report.trajectories import build_trajectory_figure, plot_trajectories

__all__ = [
    "PolygonLog",
    "build_trajectory_figure",
    "feature_collection",
    "kml_header",
    "kml_placemark",
    "lonlat_to_ring",
    "plot_trajectories",
    "polygon_feature",
    "ring_to_lonlat",
    "utc_iso",
    "write_animation",
    "write_metrics_json",
    "write_mission_outputs",
    "write_polygon_files",
]
