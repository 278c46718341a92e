"""The estimator's errors: Gauss-Markov GPS bias with its sigma and time constant, white noise held between
measurements, odometry drift in proportion to the distance flown, and exact sensors leaving the truth alone."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mission_plan.weather import SensorSpec
from mock_autopilot.sensor_errors import (
    SENSOR_RATE_HZ,
    estimated_position_ned_m,
    estimated_yaw_rad,
    initial_sensor_errors,
    sensor_step,
)


def test_gps_bias_has_its_sigma_and_time_constant() -> None:
    spec = SensorSpec(gps_bias_sigma_m=0.5, gps_bias_tau_s=60.0)
    rng = np.random.default_rng(5)
    n, dt_s, steps = 400, 1.0, 600
    state = initial_sensor_errors(n, spec, rng)
    bias = np.empty((steps, n))
    for k in range(steps):
        state = sensor_step(state, spec, k * dt_s, dt_s, np.zeros((n, 3)), rng)
        bias[k] = state.gps_bias_m[:, 0]
    assert bias.std() == pytest.approx(0.5, rel=0.05)
    lag = 60
    x = bias - bias.mean()
    assert float((x[:-lag] * x[lag:]).mean() / (x * x).mean()) == pytest.approx(math.exp(-1.0), abs=0.05)


def test_white_noise_holds_between_measurements() -> None:
    spec = SensorSpec(gps_white_sigma_m=0.3, altitude_sigma_m=0.2, heading_sigma_deg=1.0)
    rng = np.random.default_rng(1)
    state = initial_sensor_errors(1000, spec, rng)
    step_s = 0.2 / SENSOR_RATE_HZ
    held = sensor_step(state, spec, 0.0, step_s / 4.0, np.zeros((1000, 3)), rng)
    assert np.array_equal(held.white, state.white)
    later = sensor_step(held, spec, 0.0, 1.0 / SENSOR_RATE_HZ + 1e-6, np.zeros((1000, 3)), rng)
    assert not np.array_equal(later.white, state.white)
    assert later.white.std(axis=0) == pytest.approx([0.3, 0.3, 0.2, math.radians(1.0)], rel=0.1)


def test_odometry_drift_grows_with_the_distance_flown_without_gps_only() -> None:
    spec = SensorSpec(odometry_drift_frac=0.01)
    rng = np.random.default_rng(2)
    state = initial_sensor_errors(2, spec, rng)
    for k in range(100):
        state = sensor_step(state, spec, k * 0.1, 0.1, np.array([[0.5, 0.0, 0.0]] * 2), rng)
    truth = np.zeros((2, 3))
    estimate = estimated_position_ned_m(state, truth, np.array([True, False]))
    assert np.hypot(*estimate[1, :2]) == pytest.approx(0.01 * 50.0)
    assert np.allclose(estimate[0], 0.0)


def test_exact_sensors_report_the_truth() -> None:
    spec = SensorSpec()
    assert spec.exact
    rng = np.random.default_rng(3)
    state = sensor_step(initial_sensor_errors(3, spec, rng), spec, 0.0, 0.5, np.ones((3, 3)), rng)
    truth = np.arange(9.0).reshape(3, 3)
    assert np.array_equal(estimated_position_ned_m(state, truth, np.array([True, False, True])), truth)
    assert np.allclose(estimated_yaw_rad(state, np.array([0.1, 1.0, 3.0])), [0.1, 1.0, 3.0])
