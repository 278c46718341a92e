"""Dryden turbulence: the filters give the MIL-F-8785C intensities and scale lengths, whatever the step size."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mission_plan.weather import WindSpec
from mock_autopilot.world.wind import (
    dryden_scales,
    gust_speed_mps,
    initial_wind_state,
    mean_wind_ned_mps,
    wind_step,
)


def test_scales_at_ten_metres_match_the_issue_figures() -> None:
    light, moderate, severe = (dryden_scales(10.0, level) for level in ("light", "moderate", "severe"))
    assert moderate.length_uv_m == pytest.approx(67.4, abs=0.5)
    assert moderate.length_w_m == pytest.approx(10.0)
    assert (light.sigma_uv_mps, moderate.sigma_uv_mps, severe.sigma_uv_mps) == pytest.approx((1.46, 2.91, 4.37), abs=0.02)
    assert moderate.sigma_w_mps == pytest.approx(0.1 * 30 * 0.514444)
    assert dryden_scales(10.0, "none").sigma_uv_mps == 0.0


def _fit_length(acf: np.ndarray, lag_m: np.ndarray, shape: str) -> float:
    """Least-squares scale length of the Dryden autocorrelation shape to an empirical one."""
    best, best_err = 0.0, math.inf
    for length in np.linspace(1.0, 200.0, 4000):
        x = lag_m / length
        model = np.exp(-x) if shape == "first" else (1.0 - x / 2.0) * np.exp(-x)
        err = float(((acf - model) ** 2).sum())
        if err < best_err:
            best, best_err = float(length), err
    return best


def _empirical_acf(series: np.ndarray, lags: np.ndarray) -> np.ndarray:
    x = series - series.mean(axis=0)
    var = float((x * x).mean())
    return np.array([1.0 if lag == 0 else float((x[:-lag] * x[lag:]).mean()) / var for lag in lags])


def test_long_run_sigma_and_correlation_length_within_ten_percent_of_the_formulas() -> None:
    scales = dryden_scales(10.0, "moderate")
    spec = WindSpec(speed_mps=0.0, turbulence="moderate")
    rng = np.random.default_rng(7)
    n, steps, dt_s, speed = 200, 3000, 0.05, 20.0
    state = initial_wind_state(n, scales, math.inf, rng)
    velocity = np.tile([speed, 0.0, 0.0], (n, 1))
    record = np.empty((steps, n, 3))
    for k in range(steps):
        record[k], state = wind_step(state, spec, scales, k * dt_s, dt_s, velocity, rng)
    ds_m = speed * dt_s
    for axis, sigma, length, shape in ((0, scales.sigma_uv_mps, scales.length_uv_m, "first"),
                                       (1, scales.sigma_uv_mps, scales.length_uv_m, "second"),
                                       (2, scales.sigma_w_mps, scales.length_w_m, "second")):
        series = record[:, :, axis]
        assert series.std() == pytest.approx(sigma, rel=0.1)
        lags = np.unique(np.round(np.linspace(0.0, 2.0 * length, 40) / ds_m).astype(int))
        fitted = _fit_length(_empirical_acf(series, lags), lags * ds_m, shape)
        assert fitted == pytest.approx(length, rel=0.1), f"axis {axis}"


def test_the_mean_wind_blows_from_its_direction() -> None:
    assert mean_wind_ned_mps(5.0, 270.0) == pytest.approx([0.0, 5.0, 0.0], abs=1e-9)  # from the west: toward east
    assert mean_wind_ned_mps(5.0, 0.0) == pytest.approx([-5.0, 0.0, 0.0], abs=1e-9)


def test_gust_is_one_minus_cosine_over_its_duration() -> None:
    start = np.array([10.0])
    assert gust_speed_mps(9.9, start, 3.0, 3.0)[0] == 0.0
    assert gust_speed_mps(11.5, start, 3.0, 3.0)[0] == pytest.approx(3.0)
    assert gust_speed_mps(13.1, start, 3.0, 3.0)[0] == 0.0


def test_gusts_arrive_at_the_mean_interval() -> None:
    spec = WindSpec(speed_mps=5.0, gust_speed_mps=3.0, gust_duration_s=3.0, gust_interval_s=20.0)
    scales = dryden_scales(10.0, "none")
    rng = np.random.default_rng(3)
    n, dt_s = 50, 0.1
    state = initial_wind_state(n, scales, spec.gust_interval_s, rng)
    starts = 0
    previous = state.gust_start_s.copy()
    for k in range(6000):
        _, state = wind_step(state, spec, scales, k * dt_s, dt_s, np.zeros((n, 3)), rng)
        starts += int((state.gust_start_s != previous).sum())
        previous = state.gust_start_s.copy()
    assert 600.0 * n / starts == pytest.approx(23.0, rel=0.15)  # interval + duration between starts
