"""Seeds act: one seed gives the same run twice and two seeds differ, in calm (pad and start jitter) and in
weather (wind, gusts, sensor errors); agents see estimates while the record keeps the truth."""

from __future__ import annotations

import numpy as np
import pytest

from gcs.lockstep.backend_choice import BackendKind
from gcs.lockstep.engine import _LockstepRun, run_lockstep
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


def _run_for(overrides: list[str], duration_s: float) -> _LockstepRun:
    scenario = load_scenario("circle", overrides)
    steps = int(duration_s * scenario.control_rate_hz)
    run = _LockstepRun(scenario, "improved", scenario.seed, scenario.control_params("improved"), "boundary",
                       BackendKind.KINEMATIC, steps)
    for k in range(steps + 1):
        run.step(k, last=k == steps)
    return run


def test_drones_without_gps_correct_their_drift_by_ranging_their_neighbours() -> None:
    """Under ``moderate`` each GPS-less drone's odometry drifts its own way by 1 % of its path; ranging its
    neighbours (improved mode) leaves a fraction of that error."""
    run = _run_for(["weather=moderate", "seed=5"], 20.0)
    state = run.state
    drift_en_m = (state.reported_position_ned_m - state.position_ned_m)[:, [1, 0]][~run.gps]
    corrections = np.array([p.correction_en_m for p, gps in zip(run.core.positions, run.gps) if not gps])
    raw_m = np.hypot(*drift_en_m.T)
    left_m = np.hypot(*(drift_en_m - corrections).T)
    assert raw_m.mean() > 0.15
    assert left_m.mean() < 0.35 * raw_m.mean() and left_m.max() < 0.2


def test_without_the_correction_the_drift_stays() -> None:
    run = _run_for(["weather=moderate", "seed=5", "control.cooperative_position=false"], 3.0)
    assert len(run.ranging.carriers) == len(run.gps), "every drone still reads its sensor for the barrier"
    assert not any(p.correction_en_m != (0.0, 0.0) or p.flown_m for p in run.core.positions)


def test_no_drone_reads_its_sensor_when_neither_the_correction_nor_the_barrier_does() -> None:
    run = _run_for(["weather=moderate", "seed=5", "control.cooperative_position=false",
                    "control.sensed_barrier=false"], 1.0)
    assert run.ranging.carriers == []
