"""Vehicle kinematics: the paper's holonomic point (eqs 1-3) with altitude and PX4-like limits.

The paper flies each UAV as ``q̇ = u``. A real multicopter under PX4's velocity controller does not change
velocity instantly, so the commanded velocity passes through a first-order response (time constant
``response_time_s``), then PX4's limits: horizontal speed MPC_XY_VEL_MAX, climb MPC_Z_VEL_MAX_UP, descent
MPC_Z_VEL_MAX_DN and horizontal acceleration MPC_ACC_HOR. Wind is an additive ground-velocity disturbance that
the velocity loop rejects with the same time constant (a steady wind therefore leaves no steady error, as PX4's
integrator would ensure).

Everything here is NED, metres and seconds, and pure: state in, state out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from mission_plan.dynamics import KinematicLimits


@dataclass(frozen=True)
class KinematicState:
    """Position [m; local NED from the pad] and velocity [m/s; NED]."""

    position_ned_m: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    velocity_ned_mps: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))


def _clamped_components(vx: float, vy: float, vz: float, limits: KinematicLimits) -> tuple[float, float, float]:
    """PX4's setpoint clamp on plain floats (the hot path of every physics step; numpy on 3-vectors is slow)."""
    xy = math.hypot(vx, vy)
    if xy > limits.max_xy_speed_mps > 0.0:
        scale = limits.max_xy_speed_mps / xy
        vx, vy = vx * scale, vy * scale
    vz = min(max(vz, -limits.max_climb_speed_mps), limits.max_descent_speed_mps)
    return vx, vy, vz


def clamp_velocity_setpoint(velocity_ned_mps: NDArray[np.float64], limits: KinematicLimits) -> NDArray[np.float64]:
    """Clamp a velocity setpoint as PX4 does: horizontal norm to MPC_XY_VEL_MAX, vertical to the up/down limits."""
    v = np.asarray(velocity_ned_mps, dtype=float)
    return np.array(_clamped_components(float(v[0]), float(v[1]), float(v[2]), limits))


def step_kinematics(
    state: KinematicState,
    velocity_setpoint_ned_mps: NDArray[np.float64],
    limits: KinematicLimits,
    dt_s: float,
    wind_ned_mps: NDArray[np.float64] | None = None,
    ground_down_m: float = 0.0,
) -> KinematicState:
    """Advance one step of ``dt_s`` seconds towards a velocity setpoint (eq 1: q̇ = u, with PX4 limits).

    ``ground_down_m`` is the local-NED z of the ground: the vehicle never goes below it (z > ground).
    The arithmetic runs on Python floats: a fleet steps every vehicle 100 times a second.
    """
    if dt_s <= 0.0:
        return state
    sp = velocity_setpoint_ned_mps
    tx, ty, tz = _clamped_components(float(sp[0]), float(sp[1]), float(sp[2]), limits)
    v = state.velocity_ned_mps
    vx, vy, vz = float(v[0]), float(v[1]), float(v[2])
    alpha = 1.0 - math.exp(-dt_s / max(limits.response_time_s, 1e-6))
    dvx, dvy, dvz = (tx - vx) * alpha, (ty - vy) * alpha, (tz - vz) * alpha
    dv_xy = math.hypot(dvx, dvy)
    max_dv_xy = limits.max_xy_accel_mps2 * dt_s
    if dv_xy > max_dv_xy:
        scale = max_dv_xy / dv_xy
        dvx, dvy = dvx * scale, dvy * scale
    max_dv_z = limits.max_z_accel_mps2 * dt_s
    dvz = min(max(dvz, -max_dv_z), max_dv_z)
    nvx, nvy, nvz = vx + dvx, vy + dvy, vz + dvz
    if wind_ned_mps is None:
        wx = wy = wz = 0.0
    else:
        keep = 1.0 - alpha
        wx, wy, wz = float(wind_ned_mps[0]) * keep, float(wind_ned_mps[1]) * keep, float(wind_ned_mps[2]) * keep
    p = state.position_ned_m
    px = float(p[0]) + 0.5 * (vx + nvx) * dt_s + wx * dt_s
    py = float(p[1]) + 0.5 * (vy + nvy) * dt_s + wy * dt_s
    pz = float(p[2]) + 0.5 * (vz + nvz) * dt_s + wz * dt_s
    if pz > ground_down_m:
        pz = ground_down_m
        nvz = min(nvz, 0.0)
    return KinematicState(position_ned_m=np.array([px, py, pz]), velocity_ned_mps=np.array([nvx, nvy, nvz]))
