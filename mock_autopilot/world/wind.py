"""The air the vehicles fly in: mean wind, MIL-F-8785C low-altitude Dryden turbulence and discrete gusts.

Pure functions on arrays over N vehicles (one row each); the caller keeps the state and the random generator.

Turbulence (MIL-F-8785C, low altitude, h in feet, W20 the wind at 20 ft in knots: 15 / 30 / 45 for light /
moderate / severe)::

    L_w = h,   L_u = L_v = h / (0.177 + 0.000823 h)^1.2
    σ_w = 0.1 W20,   σ_u = σ_v = σ_w / (0.177 + 0.000823 h)^0.4

The longitudinal component u (along the mean wind) has the first-order Dryden spectrum, autocorrelation
``σ² exp(-ξ/L)``; the lateral v and vertical w components the second-order one, ``σ² (1 - ξ/(2L)) exp(-ξ/L)``.
Both are frozen spatial fields sampled along the path the vehicle flies through the air (Taylor's hypothesis),
so the filters advance by the distance travelled relative to the air, ``ds = |v - w_mean| dt`` (at least
``MIN_AIR_PATH_MPS dt``: a drone hovering in still air still sees the eddies drift by). Each filter is discretised
exactly over ``ds`` (transition and noise covariance of the continuous filter in closed form), so the statistics
hold at any step size.

Gusts: "1 - cosine" gusts (the MIL-F-8785C discrete gust shape) along the mean wind, ``gust_speed_mps`` peak over
``gust_duration_s``, starting at Poisson times with mean interval ``gust_interval_s``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from mission_plan.weather import WindSpec

FEET_PER_M = 1.0 / 0.3048
MPS_PER_KNOT = 0.514444
W20_KNOTS = {"none": 0.0, "light": 15.0, "moderate": 30.0, "severe": 45.0}
"""Wind speed at 20 ft [kt] of each MIL-F-8785C turbulence severity."""
MIN_HEIGHT_FT = 10.0
MAX_HEIGHT_FT = 1000.0
"""The low-altitude model holds from 10 ft up to 1000 ft; heights outside are clamped to it."""
MIN_AIR_PATH_MPS = 1.0
"""Least speed [m/s] at which the turbulent field passes a vehicle (hovering in calm air)."""


@dataclass(frozen=True)
class DrydenScales:
    """Turbulence intensities [m/s] and scale lengths [m] at one height: longitudinal/lateral (u, v), vertical w."""

    sigma_uv_mps: float
    sigma_w_mps: float
    length_uv_m: float
    length_w_m: float


def dryden_scales(height_m: float, turbulence: str) -> DrydenScales:
    """MIL-F-8785C low-altitude σ and L (module doc) at ``height_m`` above ground for a severity name."""
    h_ft = min(max(height_m * FEET_PER_M, MIN_HEIGHT_FT), MAX_HEIGHT_FT)
    base = 0.177 + 0.000823 * h_ft
    sigma_w = 0.1 * W20_KNOTS[turbulence] * MPS_PER_KNOT
    return DrydenScales(
        sigma_uv_mps=sigma_w / base ** 0.4,
        sigma_w_mps=sigma_w,
        length_uv_m=h_ft / base ** 1.2 / FEET_PER_M,
        length_w_m=h_ft / FEET_PER_M,
    )


@dataclass(frozen=True, eq=False)
class WindState:
    """The turbulence filters of N vehicles and their gusts.

    ``u`` (N,) the first-order longitudinal filter (its value is the u velocity in units of σ); ``v`` and ``w``
    (N,2) the second-order lateral and vertical filters (state ``[z, z']`` of ``z'' + 2a z' + a² z = noise``,
    unit-variance output ``a^1.5 (z + √3 z'/a)``); ``gust_start_s`` (N,) the start of each vehicle's current or next
    gust.
    """

    u: NDArray[np.float64]
    v: NDArray[np.float64]
    w: NDArray[np.float64]
    gust_start_s: NDArray[np.float64]


def initial_wind_state(n: int, scales: DrydenScales, gust_interval_s: float, rng: np.random.Generator) -> WindState:
    """Filters drawn from their stationary distribution (no warm-up transient) and each vehicle's first gust."""
    return WindState(
        u=rng.standard_normal(n),
        v=_stationary_second_order(n, 1.0 / scales.length_uv_m, rng),
        w=_stationary_second_order(n, 1.0 / scales.length_w_m, rng),
        gust_start_s=_next_gusts(np.zeros(n), gust_interval_s, rng),
    )


def _stationary_second_order(n: int, a: float, rng: np.random.Generator) -> NDArray[np.float64]:
    """Stationary state of ``z'' + 2a z' + a² z = white noise`` (unit intensity): var z = 1/(4a³), var z' = 1/(4a)."""
    return np.column_stack((rng.standard_normal(n) / math.sqrt(4.0 * a ** 3), rng.standard_normal(n) / math.sqrt(4.0 * a)))


def _next_gusts(after_s: NDArray[np.float64], interval_s: float, rng: np.random.Generator) -> NDArray[np.float64]:
    if not math.isfinite(interval_s) or interval_s <= 0.0:
        return np.full(after_s.shape, math.inf)
    return after_s + rng.exponential(interval_s, after_s.shape)


def first_order_step(x: NDArray[np.float64], ds_m: NDArray[np.float64], length_m: float,
                     noise: NDArray[np.float64]) -> NDArray[np.float64]:
    """Exact step of the unit-variance first-order filter over ``ds_m``: autocorrelation ``exp(-ξ/L)``."""
    phi = np.exp(-ds_m / length_m)
    return phi * x + np.sqrt(1.0 - phi * phi) * noise


def second_order_step(state: NDArray[np.float64], ds_m: NDArray[np.float64], length_m: float,
                      noise: NDArray[np.float64]) -> NDArray[np.float64]:
    """Exact step over ``ds_m`` of ``z'' + 2a z' + a² z = white noise`` (a = 1/L), rows ``[z, z']``.

    The system matrix A has the double eigenvalue -a, so ``exp(A s) = e^{-as} (I + (A + aI) s)``; the discrete noise
    covariance is ``∫ e^{-2aτ} f(τ) f(τ)ᵀ dτ`` over [0, s] with ``f = [τ, 1 - aτ]`` (closed form below).
    ``noise`` (N,2) are independent standard normals.
    """
    a = 1.0 / length_m
    s = ds_m
    e = np.exp(-a * s)
    z, dz = state[:, 0], state[:, 1]
    new_z = e * ((1.0 + a * s) * z + s * dz)
    new_dz = e * (-a * a * s * z + (1.0 - a * s) * dz)
    two_a = 2.0 * a
    e2 = e * e
    i0 = (1.0 - e2) / two_a
    i1 = (1.0 - e2 * (1.0 + two_a * s)) / two_a ** 2
    i2 = (2.0 - e2 * (2.0 + 2.0 * two_a * s + (two_a * s) ** 2)) / two_a ** 3
    q11 = i2
    q12 = i1 - a * i2
    q22 = i0 - 2.0 * a * i1 + a * a * i2
    l11 = np.sqrt(np.maximum(q11, 0.0))
    safe = np.where(l11 > 0.0, l11, 1.0)
    l21 = np.where(l11 > 0.0, q12 / safe, 0.0)
    l22 = np.sqrt(np.maximum(q22 - l21 * l21, 0.0))
    return np.column_stack((new_z + l11 * noise[:, 0], new_dz + l21 * noise[:, 0] + l22 * noise[:, 1]))


def second_order_output(state: NDArray[np.float64], length_m: float) -> NDArray[np.float64]:
    """Unit-variance output ``a^1.5 (z + √3 z'/a)`` of the second-order filter: the Dryden lateral/vertical shape
    ``(1 + √3 L s)/(1 + L s)²`` (stationary var ``(1 + 3)/(4a³)`` before scaling)."""
    a = 1.0 / length_m
    return a ** 1.5 * (state[:, 0] + math.sqrt(3.0) * state[:, 1] / a)


def gust_speed_mps(t_s: float, gust_start_s: NDArray[np.float64], peak_mps: float, duration_s: float) -> NDArray[np.float64]:
    """The "1 - cosine" gust along the mean wind at ``t_s`` [m/s] for gusts starting at ``gust_start_s``."""
    if duration_s <= 0.0 or peak_mps == 0.0:
        return np.zeros(gust_start_s.shape)
    phase = (t_s - gust_start_s) / duration_s
    inside = (phase >= 0.0) & (phase <= 1.0)
    return np.where(inside, 0.5 * peak_mps * (1.0 - np.cos(2.0 * math.pi * np.clip(phase, 0.0, 1.0))), 0.0)


def mean_wind_ned_mps(speed_mps: float, from_deg: float) -> NDArray[np.float64]:
    """The mean wind as a NED velocity: it blows FROM ``from_deg`` (clockwise from north), so it moves toward the
    opposite bearing."""
    toward = math.radians(from_deg) + math.pi
    return np.array([speed_mps * math.cos(toward), speed_mps * math.sin(toward), 0.0])


def wind_step(
    state: WindState,
    params: WindSpec,
    scales: DrydenScales,
    t_s: float,
    dt_s: float,
    velocity_ned_mps: NDArray[np.float64],
    rng: np.random.Generator,
) -> tuple[NDArray[np.float64], WindState]:
    """The wind [m/s NED, (N,3)] each vehicle feels at ``t_s + dt_s`` and the advanced state.

    The turbulence axes: u along the mean wind (north when there is none), v to its right, w down.
    """
    mean = mean_wind_ned_mps(params.speed_mps, params.from_deg)
    n = velocity_ned_mps.shape[0]
    air = velocity_ned_mps - mean
    ds = np.maximum(np.sqrt(np.einsum("ij,ij->i", air, air)), MIN_AIR_PATH_MPS) * dt_s
    noise = rng.standard_normal((n, 5))
    u = first_order_step(state.u, ds, scales.length_uv_m, noise[:, 0])
    v = second_order_step(state.v, ds, scales.length_uv_m, noise[:, 1:3])
    w = second_order_step(state.w, ds, scales.length_w_m, noise[:, 3:5])
    t_next = t_s + dt_s
    gust_start = state.gust_start_s
    ended = t_next > gust_start + params.gust_duration_s
    if ended.any():
        gust_start = gust_start.copy()
        gust_start[ended] = _next_gusts(gust_start[ended] + params.gust_duration_s, params.gust_interval_s, rng)
    along = scales.sigma_uv_mps * u + gust_speed_mps(t_next, gust_start, params.gust_speed_mps, params.gust_duration_s)
    across = scales.sigma_uv_mps * second_order_output(v, scales.length_uv_m)
    down = scales.sigma_w_mps * second_order_output(w, scales.length_w_m)
    heading = math.atan2(mean[1], mean[0]) if params.speed_mps > 0.0 else 0.0
    c, s = math.cos(heading), math.sin(heading)
    wind = np.empty((n, 3))
    wind[:, 0] = mean[0] + c * along - s * across
    wind[:, 1] = mean[1] + s * along + c * across
    wind[:, 2] = down
    return wind, WindState(u, v, w, gust_start)
