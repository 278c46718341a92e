"""How close two runs of the same mission must end up to count as agreeing (engines, backends): the tolerances
the processes engine is held to against the lockstep reference, in one place for the benchmark and the tests.

The processes engine flies the same onboard core with take-off, transport delays, camera frames up to one period
old and a relaying radio emulator, so its figures differ from lockstep's by a little; these bounds say how little.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

TOLERANCES: dict[str, tuple[str, float]] = {
    "encircle_time_s": ("abs", 2.0),
    "polygon_iou_final": ("abs", 0.02),
    "coverage_final": ("abs", 0.05),
    "spacing_cv_final": ("abs", 0.05),
    "tracking_rms_last_10s_m": ("abs", 0.3),
    "leader_centring_error_final_m": ("abs", 0.5),
    "min_pairwise_distance_m": ("floor", 1.0),
}
"""Metric -> (kind, bound): ``abs`` = |processes - lockstep| <= bound; ``floor`` = both runs >= bound."""


def within(metric: str, reference: float | None, other: float | None) -> bool:
    """Does ``other`` agree with ``reference`` on ``metric`` (missing or non-finite values must match exactly)?"""
    kind, bound = TOLERANCES[metric]
    if reference is None or other is None or not (math.isfinite(reference) and math.isfinite(other)):
        return reference == other
    if kind == "abs":
        return abs(other - reference) <= bound
    return reference >= bound and other >= bound


def disagreements(reference: Mapping[str, float | None], other: Mapping[str, float | None]) -> list[str]:
    """The metrics of :data:`TOLERANCES` on which two metric summaries disagree, with both values."""
    return [f"{m}: {reference.get(m)} vs {other.get(m)}" for m in TOLERANCES
            if not within(m, reference.get(m), other.get(m))]
