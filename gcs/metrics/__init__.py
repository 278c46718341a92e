"""Mission metrics of SPEC §5, pure functions on numpy arrays, and ``compute_mission_metrics`` for metrics.json."""

from gcs.metrics.centring import centring_errors_m
from gcs.metrics.coverage import CoverageGrid, CoverageStats, footprint_coverage, footprint_side_m
from gcs.metrics.effort import climb_events_from_altitude, path_lengths_m, speeds_mps
from gcs.metrics.encircle import encircle_speed_floor_s, ring_closed_time_s
from gcs.metrics.mission import compute_mission_metrics
from gcs.metrics.polygon_quality import hausdorff_m, polygon_iou
from gcs.metrics.recovery import LossEvent, recovery_time_s, vehicle_losses
from gcs.metrics.safety import SafetyStats, pairwise_safety
from gcs.metrics.spacing import SpacingStats, spacing_from_arcs, spacing_on_edge
from gcs.metrics.tracking import max_m, rms_m, tracking_errors_m

__all__ = [
    "CoverageGrid",
    "CoverageStats",
    "LossEvent",
    "SafetyStats",
    "SpacingStats",
    "centring_errors_m",
    "climb_events_from_altitude",
    "compute_mission_metrics",
    "encircle_speed_floor_s",
    "footprint_coverage",
    "footprint_side_m",
    "hausdorff_m",
    "max_m",
    "pairwise_safety",
    "path_lengths_m",
    "polygon_iou",
    "recovery_time_s",
    "ring_closed_time_s",
    "rms_m",
    "spacing_from_arcs",
    "spacing_on_edge",
    "speeds_mps",
    "tracking_errors_m",
    "vehicle_losses",
]
