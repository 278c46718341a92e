import numpy as np

from mock_autopilot.kinematics import KinematicLimits, KinematicState, clamp_velocity_setpoint, step_kinematics


def fly(setpoint: list[float], seconds: float, limits: KinematicLimits = KinematicLimits(), dt: float = 0.01) -> KinematicState:
    s = KinematicState(position_ned_m=np.array([0.0, 0.0, -10.0]), velocity_ned_mps=np.zeros(3))
    for _ in range(int(round(seconds / dt))):
        s = step_kinematics(s, np.array(setpoint, dtype=float), limits, dt)
    return s


def test_reaches_commanded_velocity_and_integrates_position() -> None:
    s = fly([1.0, 0.0, 0.0], 10.0)
    assert np.allclose(s.velocity_ned_mps, [1.0, 0.0, 0.0], atol=1e-3)
    # lag of about the response time: 10 s * 1 m/s minus ~0.3 s (plus the acceleration limit's brief effect)
    assert 9.5 < s.position_ned_m[0] < 9.8
    assert abs(s.position_ned_m[1]) < 1e-9


def test_horizontal_speed_is_clamped_to_mpc_xy_vel_max() -> None:
    limits = KinematicLimits(max_xy_speed_mps=2.0)
    s = fly([10.0, 10.0, 0.0], 5.0, limits)
    assert np.isclose(np.hypot(*s.velocity_ned_mps[:2]), 2.0, atol=1e-3)


def test_vertical_limits_differ_up_and_down() -> None:
    limits = KinematicLimits(max_climb_speed_mps=3.0, max_descent_speed_mps=1.0)
    assert clamp_velocity_setpoint(np.array([0.0, 0.0, -9.0]), limits)[2] == -3.0
    assert clamp_velocity_setpoint(np.array([0.0, 0.0, 9.0]), limits)[2] == 1.0


def test_acceleration_is_limited() -> None:
    limits = KinematicLimits(max_xy_accel_mps2=1.0, response_time_s=0.01)
    s = fly([5.0, 0.0, 0.0], 1.0, limits)
    assert s.velocity_ned_mps[0] <= 1.0 + 1e-9


def test_never_goes_below_ground() -> None:
    s = KinematicState(position_ned_m=np.array([0.0, 0.0, -0.1]), velocity_ned_mps=np.zeros(3))
    for _ in range(100):
        s = step_kinematics(s, np.array([0.0, 0.0, 1.0]), KinematicLimits(), 0.05)
    assert s.position_ned_m[2] == 0.0
