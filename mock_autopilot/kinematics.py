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

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class KinematicLimits:
    """PX4 velocity-controller limits [m/s, m/s, m/s, m/s²] and the first-order response time [s]."""

    max_xy_speed_mps: float = 12.0
    max_climb_speed_mps: float = 3.0
    max_descent_speed_mps: float = 1.5
    max_xy_accel_mps2: float = 3.0
    max_z_accel_mps2: float = 4.0
    response_time_s: float = 0.3


@dataclass(frozen=True)
class KinematicState:
    """Position [m; local NED from the pad] and velocity [m/s; NED]."""

    position_ned_m: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    velocity_ned_mps: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))


def clamp_velocity_setpoint(velocity_ned_mps: NDArray[np.float64], limits: KinematicLimits) -> NDArray[np.float64]:
    """Clamp a velocity setpoint as PX4 does: horizontal norm to MPC_XY_VEL_MAX, vertical to the up/down limits."""
    v = np.array(velocity_ned_mps, dtype=float)
    xy = float(np.hypot(v[0], v[1]))
    if xy > limits.max_xy_speed_mps > 0.0:
        v[:2] *= limits.max_xy_speed_mps / xy
    v[2] = float(np.clip(v[2], -limits.max_climb_speed_mps, limits.max_descent_speed_mps))
    return v


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
    """
    if dt_s <= 0.0:
        return state
    target = clamp_velocity_setpoint(velocity_setpoint_ned_mps, limits)
    v = state.velocity_ned_mps
    alpha = 1.0 - np.exp(-dt_s / max(limits.response_time_s, 1e-6))
    dv = (target - v) * alpha
    dv_xy = float(np.hypot(dv[0], dv[1]))
    max_dv_xy = limits.max_xy_accel_mps2 * dt_s
    if dv_xy > max_dv_xy:
        dv[:2] *= max_dv_xy / dv_xy
    dv[2] = float(np.clip(dv[2], -limits.max_z_accel_mps2 * dt_s, limits.max_z_accel_mps2 * dt_s))
    new_v = v + dv
    drift = np.zeros(3) if wind_ned_mps is None else np.asarray(wind_ned_mps, dtype=float) * (1.0 - alpha)
    new_p = state.position_ned_m + 0.5 * (v + new_v) * dt_s + drift * dt_s
    if new_p[2] > ground_down_m:
        new_p = new_p.copy()
        new_p[2] = ground_down_m
        new_v = new_v.copy()
        new_v[2] = min(new_v[2], 0.0)
    return KinematicState(position_ned_m=new_p, velocity_ned_mps=new_v)
