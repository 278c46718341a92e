"""The engines' agreement rule: absolute bounds, floors that both runs must clear, missing values must match."""

from gcs.metrics.agreement import disagreements, within


def test_abs_bounds_floors_and_missing_values() -> None:
    assert within("encircle_time_s", 10.0, 11.9) and not within("encircle_time_s", 10.0, 12.1)
    assert within("min_pairwise_distance_m", 1.4, 1.2) and not within("min_pairwise_distance_m", 1.4, 0.9)
    assert within("encircle_time_s", None, None) and not within("encircle_time_s", 10.0, None)
    reference = {"encircle_time_s": 10.0, "polygon_iou_final": 0.99}
    assert disagreements(reference, {"encircle_time_s": 10.5, "polygon_iou_final": 0.99}) == []
    assert [d.split(":")[0] for d in disagreements(reference, {"encircle_time_s": 10.5, "polygon_iou_final": 0.9})] \
        == ["polygon_iou_final"]
