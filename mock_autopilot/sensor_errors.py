"""What the autopilot's estimator gets wrong: GPS, barometric altitude, heading and odometry errors.

The estimate a vehicle flies on and reports is the truth plus these errors (the metrics are scored on the truth):

* GPS vehicles: horizontal GPS error = white noise (``gps_white_sigma_m`` per axis, a new sample each GPS
  measurement at ``SENSOR_RATE_HZ``) + a first-order Gauss-Markov bias (``gps_bias_sigma_m`` per axis, time
  constant ``gps_bias_tau_s``, discretised exactly: ``b' = φ b + σ √(1 - φ²) n``, ``φ = exp(-dt/τ)``);
* vehicles without GPS: odometry drift that grows with the distance flown, ``odometry_drift_frac`` metres per
  metre, along a direction drawn once per vehicle (a scale and heading error of visual odometry);
* every vehicle: altitude noise (``altitude_sigma_m``, white at the sensor rate) and heading noise
  (``heading_sigma_deg``, white at the sensor rate).

Pure functions over N vehicles (rows); the caller keeps the state and the random generator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from mission_plan.weather import SensorSpec

SENSOR_RATE_HZ = 10.0
"""Rate [Hz] of GPS, barometer and heading measurements: a white error holds between two of them."""


@dataclass(frozen=True, eq=False)
class SensorErrorState:
    """Errors of N vehicles: GPS bias (N,2), the white samples held since the last measurement (N,4: north, east,
    down, heading), odometry drift (N,2), each vehicle's drift direction [rad] and the measurement count."""

    gps_bias_m: NDArray[np.float64]
    white: NDArray[np.float64]
    drift_m: NDArray[np.float64]
    drift_direction_rad: NDArray[np.float64]
    samples: int


def initial_sensor_errors(n: int, params: SensorSpec, rng: np.random.Generator) -> SensorErrorState:
    """Bias from its stationary distribution, a first white sample, no drift yet, drift directions drawn."""
    return SensorErrorState(
        gps_bias_m=params.gps_bias_sigma_m * rng.standard_normal((n, 2)),
        white=_white(n, params, rng),
        drift_m=np.zeros((n, 2)),
        drift_direction_rad=rng.uniform(0.0, 2.0 * math.pi, n),
        samples=0,
    )


def _white(n: int, params: SensorSpec, rng: np.random.Generator) -> NDArray[np.float64]:
    scale = np.array([params.gps_white_sigma_m, params.gps_white_sigma_m, params.altitude_sigma_m,
                      math.radians(params.heading_sigma_deg)])
    return scale * rng.standard_normal((n, 4))


def sensor_step(
    state: SensorErrorState,
    params: SensorSpec,
    t_s: float,
    dt_s: float,
    moved_ned_m: NDArray[np.float64],
    rng: np.random.Generator,
) -> SensorErrorState:
    """Advance the errors from ``t_s`` over ``dt_s``; ``moved_ned_m`` (N,3) is each vehicle's true displacement."""
    n = moved_ned_m.shape[0]
    phi = math.exp(-dt_s / params.gps_bias_tau_s)
    bias = phi * state.gps_bias_m + params.gps_bias_sigma_m * math.sqrt(1.0 - phi * phi) * rng.standard_normal((n, 2))
    samples = int(math.floor((t_s + dt_s) * SENSOR_RATE_HZ + 1e-9))
    white = _white(n, params, rng) if samples != state.samples else state.white
    distance = np.hypot(moved_ned_m[:, 0], moved_ned_m[:, 1]) * params.odometry_drift_frac
    drift = state.drift_m + distance[:, None] * np.column_stack(
        (np.cos(state.drift_direction_rad), np.sin(state.drift_direction_rad)))
    return SensorErrorState(bias, white, drift, state.drift_direction_rad, samples)


def estimated_position_ned_m(state: SensorErrorState, true_ned_m: NDArray[np.float64],
                             has_gps: NDArray[np.bool_]) -> NDArray[np.float64]:
    """The estimator's position (N,3): GPS error where a GPS is fitted, odometry drift elsewhere, altitude noise."""
    estimate = np.array(true_ned_m, dtype=float, copy=True)
    horizontal = np.where(has_gps[:, None], state.gps_bias_m + state.white[:, :2], state.drift_m)
    estimate[:, :2] += horizontal
    estimate[:, 2] += state.white[:, 2]
    return estimate


def estimated_yaw_rad(state: SensorErrorState, true_yaw_rad: NDArray[np.float64]) -> NDArray[np.float64]:
    """The estimator's heading (N,) [rad, 0..2π)."""
    return np.mod(true_yaw_rad + state.white[:, 3], 2.0 * math.pi)
