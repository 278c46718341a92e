"""The ground station's caged flood polygon and plain ring geometry (SPEC §6)."""

from gcs.polygon.caged import caged_polygon
from gcs.polygon.growth import area_growth_rate_m2ps, equivalent_radius_m, polygon_growth_rate_m2ps
from gcs.polygon.ring import (
    RingProjection,
    densify_ring,
    distance_to_ring_m,
    open_ring,
    orient_ccw,
    project_onto_ring,
    ring_area_m2,
    ring_perimeter_m,
    signed_area_m2,
)

__all__ = [
    "RingProjection",
    "area_growth_rate_m2ps",
    "caged_polygon",
    "densify_ring",
    "distance_to_ring_m",
    "equivalent_radius_m",
    "open_ring",
    "orient_ccw",
    "polygon_growth_rate_m2ps",
    "project_onto_ring",
    "ring_area_m2",
    "ring_perimeter_m",
    "signed_area_m2",
]
