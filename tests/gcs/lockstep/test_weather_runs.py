"""Seeds act: one seed gives the same run twice and two seeds differ, in calm (pad and start jitter) and in
weather (wind, gusts, sensor errors); agents see estimates while the record keeps the truth."""

from __future__ import annotations

import numpy as np
import pytest

from gcs.lockstep.engine import run_lockstep
from gcs.scenario import load_scenario

DURATION_S = 2.0


def _positions(weather: str, seed: int) -> np.ndarray:
    scenario = load_scenario("circle", [f"weather={weather}", f"seed={seed}"])
    return run_lockstep(scenario, "improved", duration_s=DURATION_S, cameras="boundary").record.positions_enu_m


@pytest.mark.parametrize("weather", ["calm", "moderate"])
def test_one_seed_repeats_and_two_seeds_differ(weather: str) -> None:
    first, again, other = _positions(weather, 1), _positions(weather, 1), _positions(weather, 2)
    assert np.array_equal(first, again)
    assert not np.allclose(first, other, atol=1e-3)


def test_weather_moves_the_fleet_off_its_calm_path() -> None:
    calm, windy = _positions("calm", 3), _positions("moderate", 3)
    assert np.abs(windy - calm).max() > 0.05
