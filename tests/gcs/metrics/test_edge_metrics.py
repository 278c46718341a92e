import math

import numpy as np
import pytest

from gcs.metrics import (
    encircle_speed_floor_s,
    hausdorff_m,
    max_m,
    polygon_iou,
    ring_closed_time_s,
    rms_m,
    spacing_from_arcs,
    spacing_on_edge,
    tracking_errors_m,
)
from mock_autopilot.world.flood_model import ExpandingCircle

CIRCLE = ExpandingCircle(radius_start_m=16.0, radius_end_m=16.0).boundary_en_m(0.0)


def on_circle(angles_rad: np.ndarray, radius_m: float = 16.0) -> np.ndarray:
    return np.stack([radius_m * np.cos(angles_rad), radius_m * np.sin(angles_rad)], axis=-1)


def test_a_perfect_ring_has_cv_zero_and_gap_ratio_one() -> None:
    stats = spacing_on_edge(on_circle(np.arange(8) * math.pi / 4 + 0.1), CIRCLE)
    assert stats.cv == pytest.approx(0.0, abs=1e-3)
    assert stats.max_gap_ratio == pytest.approx(1.0, abs=1e-3)
    assert stats.gaps_m.sum() == pytest.approx(2 * math.pi * 16.0, rel=1e-3)


def test_spacing_statistics_of_known_gaps() -> None:
    stats = spacing_from_arcs([0.0, 1.0, 4.0, 5.0], perimeter_m=10.0)  # gaps 1, 3, 1, 5
    assert np.allclose(stats.gaps_m, [1.0, 3.0, 1.0, 5.0])
    assert stats.cv == pytest.approx(np.std([1, 3, 1, 5]) / 2.5)
    assert stats.max_gap_ratio == pytest.approx(2.0)
    assert math.isnan(spacing_from_arcs([3.0], 10.0).cv)


def test_tracking_error_is_the_distance_to_the_true_edge() -> None:
    drones = np.array([[16.0, 0.0, 10.0], [0.0, 17.0, 10.0], [-15.0, 0.0, 10.0]])
    errors = tracking_errors_m(drones, CIRCLE)
    assert np.allclose(errors, [0.0, 1.0, 1.0], atol=2e-3)
    assert rms_m(errors) == pytest.approx(math.sqrt(2 / 3), abs=2e-3)
    assert max_m([np.nan, 2.0, 1.0]) == 2.0
    assert math.isnan(rms_m([]))


def test_octagon_against_its_circle_iou_and_hausdorff() -> None:
    octagon = on_circle(np.arange(8) * math.pi / 4)
    assert polygon_iou(octagon, CIRCLE) == pytest.approx(2 * math.sqrt(2) / math.pi, abs=2e-3)
    sagitta = 16.0 * (1 - math.cos(math.pi / 8))
    assert hausdorff_m(octagon, CIRCLE) == pytest.approx(sagitta, abs=0.02)
    assert polygon_iou(CIRCLE, CIRCLE) == pytest.approx(1.0)
    assert polygon_iou(np.zeros((0, 2)), CIRCLE) == 0.0
    assert math.isnan(hausdorff_m(np.zeros((2, 2)), CIRCLE))


def test_ring_closes_when_the_far_gap_shrinks() -> None:
    t = np.arange(5.0)
    assert ring_closed_time_s(t, [4.0, 3.0, 1.6, 1.4, 1.1]) == 3.0
    assert math.isnan(ring_closed_time_s(t, [4.0, 3.0, 2.0, np.nan, 1.6]))
    assert encircle_speed_floor_s(2 * math.pi * 14.0, 1.0) == pytest.approx(43.98, abs=0.01)
