"""The vehicle dynamics a mission plans for: PX4's velocity-controller limits and the plant's response time.

Both engines read the same values: the lockstep kinematics directly, a mock PX4 as its MPC_* parameters
(``mock_autopilot.dynamics_params``) plus ``response_time_s``.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class KinematicLimits:
    """PX4 velocity-controller limits [m/s, m/s, m/s, m/s², m/s²] and the first-order response time [s]."""

    max_xy_speed_mps: float = 12.0
    max_climb_speed_mps: float = 3.0
    max_descent_speed_mps: float = 1.5
    max_xy_accel_mps2: float = 3.0
    max_z_accel_mps2: float = 4.0
    response_time_s: float = 0.3
