"""``large``'s launch field leaves the improved collision barrier's minimum between any two jittered pads, so a
fleet hovering over its pads is at rest whatever it waits for: where the flood finds the drones does not depend on
how long the processes engine took to bring the last agent up (lockstep starts the flood at once)."""

from __future__ import annotations

import numpy as np
import pytest

from comms.radio_model import squared_distances
from mission_plan.scenario_files import load_scenario


@pytest.mark.parametrize("seed", [1, 2, 3, 4, 5, 17])
def test_large_pads_keep_the_barrier_minimum_after_the_jitter(seed: int) -> None:
    scenario = load_scenario("large", [f"seed={seed}"])
    pads_en_m = np.array([v.pad_enu_m[:2] for v in scenario.vehicles])
    gaps_m = np.sqrt(squared_distances(pads_en_m, pads_en_m))
    np.fill_diagonal(gaps_m, np.inf)
    assert len(pads_en_m) == 208
    assert gaps_m.min() >= scenario.control_params("improved").safety_min_distance_m
