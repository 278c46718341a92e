"""Perception under hard imagery and a tilting camera, scored against the renderer's truth (the weather targets:
pooled water IoU >= 0.95, midpoint error p95 <= 0.3 m at 10 m, on seeds not used while developing).

The default run checks a few conditions on a small held-out sample; ``-m slow`` runs the 300-pose table of
docs/PERCEPTION.md (``bench/perception_conditions.py``). Conditions whose target is not met are marked as expected
failures with the measured figure, so the table and the tests say the same thing.
"""

from __future__ import annotations

import pytest

from bench.perception_conditions import CONDITIONS, HELD_OUT, score_condition
from mock_autopilot.camera.truth import ACCURACY_FLOODS

FLOODS = list(ACCURACY_FLOODS)
NOT_MET = {
    "rough": "turbid water with shadows, debris, JPEG 60 and noise 6: pooled IoU 0.63, midpoint p95 1.4 m",
}
"""Conditions whose targets perception does not meet (docs/PERCEPTION.md has the figures)."""


def check_targets(name: str, frames: int) -> None:
    spec, tilt_deg = CONDITIONS[name]
    score = score_condition(name, spec, tilt_deg, FLOODS, frames, HELD_OUT)
    assert score.frames_with_edge >= frames // 2
    assert score.pooled_iou >= 0.95, score
    assert score.midpoint_err_m_p95 <= 0.3, score


@pytest.mark.parametrize("name", ["noise_sigma", "cloud_shadow_cover", "tilt", "moderate"])
def test_a_held_out_sample_meets_the_targets(name: str) -> None:
    check_targets(name, 24)


@pytest.mark.slow
@pytest.mark.parametrize("name", [
    pytest.param(name, marks=pytest.mark.xfail(reason=NOT_MET[name], strict=True)) if name in NOT_MET else name
    for name in CONDITIONS])
def test_each_condition_over_300_held_out_poses(name: str) -> None:
    check_targets(name, 300)
