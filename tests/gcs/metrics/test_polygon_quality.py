"""Polygon IoU on partly overlapping shapes with an IoU worked out by hand, both ways round."""

from __future__ import annotations

import math

import pytest

from gcs.metrics.polygon_quality import polygon_iou


def square(x0: float, y0: float, side: float) -> list[tuple[float, float]]:
    return [(x0, y0), (x0 + side, y0), (x0 + side, y0 + side), (x0, y0 + side)]


@pytest.mark.parametrize(("a", "b", "iou"), [
    # 2x2 and 4x4 squares sharing a 1x2 strip: 2 / (4 + 16 - 2)
    (square(0, 0, 2), square(1, 0, 4), 2.0 / 18.0),
    # unit square inside a 3x3 one, off centre: 1 / 9
    (square(0.5, 0.5, 1), square(0, 0, 3), 1.0 / 9.0),
    # two 2x2 squares overlapping in a 1x1 corner: 1 / 7
    (square(0, 0, 2), square(1, 1, 2), 1.0 / 7.0),
])
def test_iou_of_partly_overlapping_shapes_is_known_and_symmetric(a, b, iou) -> None:  # noqa: ANN001
    assert polygon_iou(a, b) == pytest.approx(iou, rel=1e-12)
    assert polygon_iou(b, a) == pytest.approx(iou, rel=1e-12)


def test_iou_edge_cases() -> None:
    assert polygon_iou(square(0, 0, 2), square(0, 0, 2)) == pytest.approx(1.0)
    assert polygon_iou(square(0, 0, 1), square(5, 5, 1)) == 0.0
    assert polygon_iou([], square(0, 0, 1)) == 0.0
    assert math.isnan(polygon_iou([], []))
