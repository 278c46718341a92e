"""How PX4's velocity controller holds a multicopter against the wind: the part of the motion the air adds.

The vehicle's commanded motion is the reference response of :mod:`mock_autopilot.kinematics` (first-order towards
the setpoint within MPC_ACC_HOR, the paper's ``q̇ = u`` with PX4's limits): in still air the vehicle flies it
exactly. In moving air the body feels linear drag toward the air velocity, ``c (w - v)``; the controller thrusts
``a_ref + c v`` (the reference acceleration plus the drag of its own motion, the steady part of PX4's integrator)
and corrects the velocity error ``e = v - v_ref`` with PX4's PI velocity loop (MPC_XY_VEL_P_ACC / _I_ACC,
MPC_Z_VEL_P_ACC / _I_ACC). The horizontal thrust is limited by the tilt limit MPC_TILTMAX_AIR
(``|a_xy| <= g tan θmax``). Hence ``e' = c w - Kp e - I`` with ``I' = Ki e``: a gust or an eddy pushes the vehicle
until the integrator catches up (tracking error, hover drift, overshoot), a steady wind leaves no steady error,
and a wind beyond the tilt limit blows the vehicle away.

The tilt the vehicle shows (ATTITUDE, the camera's attitude) follows from the horizontal thrust acceleration.
Pure functions over N vehicles (rows), NED, metres and seconds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

GRAVITY_MPS2 = 9.81


@dataclass(frozen=True)
class VelocityLoopGains:
    """PX4's velocity PI gains [1/s, 1/s²], its tilt limit [deg] and the plant's linear drag [1/s]."""

    xy_p: float = 1.8
    xy_i: float = 0.4
    z_p: float = 4.0
    z_i: float = 2.0
    tilt_max_deg: float = 45.0
    drag_per_s: float = 0.3


@dataclass(frozen=True, eq=False)
class DisturbanceState:
    """Velocity error from the wind ``e`` [m/s, (N,3)] and the velocity loop's integrator [m/s², (N,3)]."""

    error_mps: NDArray[np.float64]
    integrator_mps2: NDArray[np.float64]


def no_disturbance(n: int) -> DisturbanceState:
    return DisturbanceState(np.zeros((n, 3)), np.zeros((n, 3)))


def disturbance_step(
    state: DisturbanceState,
    reference_velocity_ned_mps: NDArray[np.float64],
    reference_accel_ned_mps2: NDArray[np.float64],
    wind_ned_mps: NDArray[np.float64],
    gains: VelocityLoopGains,
    dt_s: float,
) -> tuple[DisturbanceState, NDArray[np.float64]]:
    """Advance ``e`` and the integrator over ``dt_s`` (module doc); returns them and the thrust acceleration
    [m/s², (N,3) NED, gravity excluded] the vehicle flies with (its tilt)."""
    e = state.error_mps
    integ = state.integrator_mps2
    c = gains.drag_per_s
    velocity = reference_velocity_ned_mps + e
    kp = np.array([gains.xy_p, gains.xy_p, gains.z_p])
    ki = np.array([gains.xy_i, gains.xy_i, gains.z_i])
    correction = -kp * e - integ
    thrust = reference_accel_ned_mps2 + c * velocity + correction
    limit = GRAVITY_MPS2 * math.tan(math.radians(gains.tilt_max_deg))
    xy = np.hypot(thrust[:, 0], thrust[:, 1])
    over = xy > limit
    if over.any():
        thrust[over, :2] *= (limit / xy[over])[:, None]
    accel = thrust + c * (wind_ned_mps - velocity)
    new_e = e + (accel - reference_accel_ned_mps2) * dt_s
    new_integ = integ + ki * e * dt_s
    return DisturbanceState(new_e, new_integ), thrust


def tilt_from_thrust(thrust_ned_mps2: NDArray[np.float64], yaw_rad: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(roll, pitch) [rad, (N,)] of a multicopter whose rotors push ``thrust`` + lift against gravity: pitch down
    (negative) to accelerate forward, roll right (positive) to accelerate right."""
    c, s = np.cos(yaw_rad), np.sin(yaw_rad)
    forward = c * thrust_ned_mps2[:, 0] + s * thrust_ned_mps2[:, 1]
    right = -s * thrust_ned_mps2[:, 0] + c * thrust_ned_mps2[:, 1]
    lift = GRAVITY_MPS2 - thrust_ned_mps2[:, 2]
    return np.arctan2(right, lift), -np.arctan2(forward, lift)
