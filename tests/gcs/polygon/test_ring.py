import math

import numpy as np

from gcs.polygon import (
    area_growth_rate_m2ps,
    densify_ring,
    equivalent_radius_m,
    orient_ccw,
    polygon_growth_rate_m2ps,
    project_onto_ring,
    ring_area_m2,
    ring_perimeter_m,
    signed_area_m2,
)
from gcs.mission_record import PolygonSample

SQUARE_CCW = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])


def test_shoelace_sign_follows_orientation_and_closing_vertex_is_ignored() -> None:
    assert signed_area_m2(SQUARE_CCW) == 4.0
    assert signed_area_m2(SQUARE_CCW[::-1]) == -4.0
    closed = np.vstack([SQUARE_CCW, SQUARE_CCW[:1]])
    assert ring_area_m2(closed) == 4.0
    assert ring_perimeter_m(closed) == 8.0
    assert np.array_equal(orient_ccw(SQUARE_CCW[::-1]), SQUARE_CCW)
    assert signed_area_m2(orient_ccw(SQUARE_CCW[::-1])) > 0


def test_densify_keeps_the_shape_and_bounds_segment_length() -> None:
    dense = densify_ring(SQUARE_CCW, 0.3)
    seg = np.linalg.norm(np.roll(dense, -1, axis=0) - dense, axis=1)
    assert seg.max() <= 0.3 + 1e-12
    assert math.isclose(ring_perimeter_m(dense), 8.0)
    assert math.isclose(ring_area_m2(dense), 4.0)


def test_projection_gives_distance_arc_and_outward_positive_offset() -> None:
    proj = project_onto_ring([[1.0, -1.0], [1.0, 0.5], [3.0, 3.0]], SQUARE_CCW)
    assert np.allclose(proj.distance_m, [1.0, 0.5, math.sqrt(2)])
    assert np.allclose(proj.arc_m, [1.0, 1.0, 4.0])
    assert np.allclose(proj.offset_m, [1.0, -0.5, math.sqrt(2)])
    assert proj.perimeter_m == 8.0
    assert np.allclose(proj.nearest_en_m, [[1.0, 0.0], [1.0, 0.0], [2.0, 2.0]])


def test_growth_rate_is_the_fitted_slope_of_recent_area() -> None:
    t = np.arange(0.0, 20.0, 0.5)
    area = 100.0 + 3.0 * t
    assert math.isclose(area_growth_rate_m2ps(t, area, window_s=5.0), 3.0)
    samples = [PolygonSample(float(tk), SQUARE_CCW * (1.0 + 0.1 * tk)) for tk in t]
    rate = polygon_growth_rate_m2ps(samples, window_s=1.0)
    expected = 4.0 * 2 * 0.1 * (1 + 0.1 * 19.25)  # d/dt of 4 (1 + 0.1 t)^2 near the end
    assert abs(rate - expected) < 0.05
    assert math.isnan(area_growth_rate_m2ps([1.0], [2.0]))
    assert math.isclose(equivalent_radius_m(math.pi * 16.0**2), 16.0)
