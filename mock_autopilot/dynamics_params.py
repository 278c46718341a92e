"""The vehicle dynamics of a mission plan as the PX4 parameters that set them (one mapping for every backend).

The plan's ``[kinematics]`` table gives PX4's velocity-controller limits in SI units; a mock PX4 reads them as its
MPC_* parameters, exactly as a real PX4 would be configured. ``response_time_s`` is the plant's first-order velocity
response, not a PX4 parameter: it travels in :class:`mock_autopilot.vehicle.VehicleConfig` instead.
"""

from __future__ import annotations

from mock_autopilot.kinematics import KinematicLimits


def px4_params(limits: KinematicLimits, takeoff_altitude_m: float) -> dict[str, float]:
    """MPC_* limits and MIS_TAKEOFF_ALT for one vehicle of the plan."""
    return {
        "MPC_XY_VEL_MAX": limits.max_xy_speed_mps,
        "MPC_Z_VEL_MAX_UP": limits.max_climb_speed_mps,
        "MPC_Z_VEL_MAX_DN": limits.max_descent_speed_mps,
        "MPC_ACC_HOR": limits.max_xy_accel_mps2,
        "MPC_ACC_UP_MAX": limits.max_z_accel_mps2,
        "MIS_TAKEOFF_ALT": takeoff_altitude_m,
    }
