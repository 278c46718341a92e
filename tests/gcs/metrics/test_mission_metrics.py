import json
import math

import numpy as np
import pytest

from gcs.metrics import compute_mission_metrics
from gcs.metrics.synthetic_record import synthetic_circle_record
from gcs.mission_record import MissionRecord


@pytest.fixture(scope="module")
def circle_with_a_loss():
    record, flood = synthetic_circle_record(loss_at_s=40.0, seed=1)
    return record, flood, compute_mission_metrics(record, flood, 60.0)


def test_metrics_are_plain_json_with_summary_and_series(circle_with_a_loss) -> None:
    record, _, metrics = circle_with_a_loss
    text = json.dumps(metrics, allow_nan=False)
    back = json.loads(text)
    assert back["scenario"] == "circle" and back["schema"] == "floodwatch.metrics/1"
    assert len(back["series"]["t_s"]) == len(record.t_s) == 601
    assert len(back["series"]["spacing_cv"]) == 601
    assert 100 <= len(back["coverage_series"]["t_s"]) <= 130
    assert set(back["per_vehicle"]) == {str(v) for v in record.vehicle_ids}


def test_an_ideal_scripted_run_scores_as_expected(circle_with_a_loss) -> None:
    _, _, metrics = circle_with_a_loss
    s = metrics["summary"]
    assert s["tracking_rms_m"] < 0.01  # drones sit exactly on the edge
    assert s["spacing_cv_final"] == pytest.approx(0.0, abs=0.01)
    assert s["max_gap_ratio_final"] == pytest.approx(1.0, abs=0.02)
    assert 15.0 < s["ring_closed_time_s"] < 20.0  # the script fans out over 20 s
    assert s["encircle_time_source"].startswith("truth")
    assert s["polygon_iou_final"] >= 0.97
    assert s["polygon_hausdorff_final_m"] < 1.0
    assert 0.8 < s["drone_ring_iou_final"] < 0.9  # 7 vertices after the loss
    assert s["leader_centring_error_final_m"] == pytest.approx(0.0, abs=1e-9)
    assert s["min_pairwise_distance_m"] > 1.0 and s["near_miss_pairs"] == 0
    assert 0.9 < s["coverage_final"] <= s["coverage_upper_bound_final"] <= 1.0
    assert 0.0 < s["overlap_efficiency_final"] <= 1.0


def test_the_loss_is_reported_with_its_recovery_time(circle_with_a_loss) -> None:
    record, _, metrics = circle_with_a_loss
    [loss] = metrics["losses"]
    assert loss["vehicle_id"] == record.vehicle_ids[-1] and loss["role"] == "boundary"
    assert loss["t_s"] == pytest.approx(40.0)
    assert 0.0 < loss["recovery_time_s"] <= 5.0  # the script re-spaces linearly over 5 s
    assert metrics["per_vehicle"][str(record.vehicle_ids[-1])]["alive_at_end"] is False


def test_engine_encircle_time_and_climb_counts_take_precedence() -> None:
    record, flood = synthetic_circle_record(duration_s=10.0, polygon_period_s=2.0)
    record.encircle_time_s = 7.5
    record.climb_events = [1] * len(record.vehicle_ids)
    s = compute_mission_metrics(record, flood, 60.0)["summary"]
    assert s["encircle_time_s"] == 7.5 and s["encircle_time_source"] == "engine"
    assert s["climb_events_total"] == len(record.vehicle_ids)


def test_footprints_fall_back_to_altitude_and_fov_and_bad_shapes_are_refused() -> None:
    record, flood = synthetic_circle_record(duration_s=5.0, polygon_period_s=5.0)
    wide = compute_mission_metrics(record, flood, 60.0)["summary"]["coverage_final"]
    record.footprint_side_m = np.zeros((0, 0))
    narrow = compute_mission_metrics(record, flood, 20.0)["summary"]["coverage_final"]
    assert narrow < wide
    broken = MissionRecord("x", "m", "e", 0, [1, 2], ["leader", "boundary"], t_s=np.zeros(3), positions_enu_m=np.zeros((3, 1, 3)))
    with pytest.raises(ValueError, match="positions_enu_m"):
        compute_mission_metrics(broken, flood, 60.0)


def test_a_record_without_polygons_or_leader_gives_nulls_not_errors() -> None:
    record, flood = synthetic_circle_record(duration_s=3.0, n_followers=0, polygon_period_s=1.0)
    record.polygons = []
    record.roles = ["follower"] + record.roles[1:]
    metrics = compute_mission_metrics(record, flood, 60.0)
    assert metrics["summary"]["polygon_iou_final"] is None
    assert metrics["summary"]["leader_centring_error_final_m"] is None
    assert math.isfinite(metrics["summary"]["coverage_final"])


@pytest.mark.parametrize("samples", [0, 1, 2])
def test_empty_and_very_short_records_give_json_not_errors(samples: int) -> None:
    from mock_autopilot.world.flood_model import ExpandingCircle

    positions = np.ones((samples, 3, 3)) * np.array([[0.0, 0.0, 10.0], [12.0, 0.0, 10.0], [3.0, 3.0, 10.0]])
    record = MissionRecord("circle", "m", "e", 0, [1, 2, 3], ["leader", "boundary", "follower"],
                           t_s=np.arange(samples) * 0.1, positions_enu_m=positions)
    metrics = compute_mission_metrics(record, ExpandingCircle(), 60.0)
    json.dumps(metrics, allow_nan=False)
    assert metrics["summary"]["samples"] == samples
    assert (metrics["summary"]["coverage_final"] is None) == (samples == 0)


def test_relayed_copies_refused_in_summary_and_per_vehicle() -> None:
    record, flood = synthetic_circle_record(duration_s=3.0, polygon_period_s=1.0)
    n = len(record.vehicle_ids)
    plain = compute_mission_metrics(record, flood, 60.0)
    assert plain["summary"]["relayed_copies_refused"] is None and plain["summary"]["relayed_copies_refused_ground"] is None
    assert all(v["relayed_copies_refused"] is None for v in plain["per_vehicle"].values())
    record.refused_copies = [None, 4] + [1] * (n - 2)
    record.ground_refused_copies = 2
    metrics = compute_mission_metrics(record, flood, 60.0)
    assert metrics["summary"]["relayed_copies_refused"] == 4 + n - 2
    assert metrics["summary"]["relayed_copies_refused_ground"] == 2
    per_vehicle = metrics["per_vehicle"]
    assert per_vehicle[str(record.vehicle_ids[0])]["relayed_copies_refused"] is None
    assert per_vehicle[str(record.vehicle_ids[1])]["relayed_copies_refused"] == 4
