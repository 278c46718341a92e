"""PX4's position controller reduced to what the mock flies: per mode, the velocity [m/s NED] and yaw the
vehicle asks its velocity loop for, the yaw rate limit, and the unpowered fall of a disarmed vehicle.

The position loop is PX4's P controller on the position error (MPC_XY_P, MPC_Z_P) with the horizontal speed
capped at the cruise speed and the vertical within MPC_Z_VEL_MAX_UP / _DN (or MPC_TKO_SPEED, MPC_LAND_SPEED).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from comms.px4 import Px4Mode
from mock_autopilot.kinematics import KinematicState
from mock_autopilot.setpoints import velocity_command_ned
from mock_autopilot.vehicle_state import GRAVITY_MPS2, RtlPhase, VehicleState

TAKEOFF_ACCEPT_M = 0.2
RTL_HOME_REACHED_M = 0.5
_HOLD_ALTITUDE_MODES = (Px4Mode.ALTCTL, Px4Mode.STABILIZED, Px4Mode.MANUAL)


def goto(
    position_ned_m: NDArray[np.float64], target: NDArray[np.float64], xy_gain: float, z_gain: float,
    speed_xy: float, climb: float, descent: float,
) -> NDArray[np.float64]:
    """PX4's position loop: P on the position error, horizontal speed capped, vertical within climb/descent."""
    p = position_ned_m
    vx, vy = xy_gain * (float(target[0]) - float(p[0])), xy_gain * (float(target[1]) - float(p[1]))
    n = math.hypot(vx, vy)
    if n > speed_xy > 0.0:
        vx, vy = vx * speed_xy / n, vy * speed_xy / n
    vz = min(max(z_gain * (float(target[2]) - float(p[2])), -climb), descent)
    return np.array([vx, vy, vz])


def cruise_speed_mps(v: VehicleState) -> float:
    """DO_CHANGE_SPEED's speed, else MPC_XY_CRUISE."""
    return v.cruise_speed_mps if v.cruise_speed_mps is not None else v.params["MPC_XY_CRUISE"]


def _goto(v: VehicleState, target: NDArray[np.float64], speed_xy: float, climb: float, descent: float) -> NDArray[np.float64]:
    return goto(v.position_ned_m, target, v.params["MPC_XY_P"], v.params["MPC_Z_P"], speed_xy, climb, descent)


def velocity_command(v: VehicleState, t_s: float) -> tuple[NDArray[np.float64], float, float]:
    """Velocity [m/s NED] the current mode asks for, plus a yaw target [rad] (NaN: none) and yaw rate [rad/s].

    Offboard also moves the hold point along with the vehicle (so a later Hold stops where it is), and RTL
    advances its phase: the only state this function changes.
    """
    up, down = v.params["MPC_Z_VEL_MAX_UP"], v.params["MPC_Z_VEL_MAX_DN"]
    mode = v.mode
    nan = math.nan
    if mode == Px4Mode.OFFBOARD:
        sp = v.offboard_setpoint
        if sp is None or not sp.flyable or not v.offboard_fresh(t_s):  # PX4's failsafe setpoint: hover
            return _goto(v, v.hold_ned, cruise_speed_mps(v), up, down), nan, 0.0
        command = velocity_command_ned(
            sp, v.position_ned_m, v.velocity_ned_mps, v.params["MPC_XY_P"], v.params["MPC_Z_P"],
            v.config.response_time_s,
        )
        if v.on_ground() and command[2] > 0.0:
            command[2] = 0.0
        v.hold_ned = v.position_ned_m.copy()
        yaw_rate = sp.yaw_rate_rad_s if math.isfinite(sp.yaw_rate_rad_s) else 0.0
        return command, sp.yaw_rad, yaw_rate
    if mode == Px4Mode.AUTO_TAKEOFF:
        target = np.array([v.hold_ned[0], v.hold_ned[1], v.takeoff_down_m])
        return _goto(v, target, cruise_speed_mps(v), v.params["MPC_TKO_SPEED"], down), nan, 0.0
    if mode == Px4Mode.AUTO_LAND:
        command = _goto(v, v.hold_ned, cruise_speed_mps(v), up, down)
        command[2] = v.params["MPC_LAND_SPEED"]
        return command, nan, 0.0
    if mode == Px4Mode.AUTO_RTL:
        return _rtl_command(v, up, down), nan, 0.0
    if v.landed_for(0.0):
        # A multicopter armed on the ground in Hold (or a manual mode without stick input) stays there at idle until
        # a take-off is commanded, as PX4 does: holding its noisy altitude estimate would lift it and make the land
        # detector report it airborne, and a client that sees "in air" never sends the take-off.
        return np.zeros(3), nan, 0.0
    command = _goto(v, v.hold_ned, cruise_speed_mps(v), up, down)
    if mode in _HOLD_ALTITUDE_MODES:
        command[:2] = 0.0
    return command, nan, 0.0


def _rtl_command(v: VehicleState, up: float, down: float) -> NDArray[np.float64]:
    p = v.position_ned_m
    home = v.home_ned_m
    return_down_m = min(float(p[2]), float(home[2]) - v.params["RTL_RETURN_ALT"])
    if v.rtl_phase is RtlPhase.CLIMB:
        if p[2] <= return_down_m + TAKEOFF_ACCEPT_M:
            v.rtl_phase = RtlPhase.RETURN
            v.hold_ned = np.array([home[0], home[1], p[2]])
        else:
            command = _goto(v, np.array([p[0], p[1], return_down_m]), 0.0, up, down)
            command[:2] = 0.0
            return command
    if v.rtl_phase is RtlPhase.RETURN:
        if math.hypot(p[0] - home[0], p[1] - home[1]) < RTL_HOME_REACHED_M:
            v.rtl_phase = RtlPhase.LAND
        else:
            return _goto(v, v.hold_ned, cruise_speed_mps(v), up, down)
    command = _goto(v, np.array([home[0], home[1], p[2]]), cruise_speed_mps(v), up, down)
    command[2] = v.params["MPC_LAND_SPEED"]
    return command


def yaw_step(yaw_rad: float, yaw_target_rad: float, yaw_rate_rad_s: float, max_rate_rad_s: float, dt_s: float) -> tuple[float, float]:
    """(new yaw [rad, 0..2π), rate [rad/s]): toward the target if there is one, else at the commanded rate,
    the rate within MPC_YAWRAUTO_MAX."""
    if math.isfinite(yaw_target_rad):
        error = (yaw_target_rad - yaw_rad + math.pi) % (2 * math.pi) - math.pi
        rate = min(max(error / max(dt_s, 0.2), -max_rate_rad_s), max_rate_rad_s)
    else:
        rate = min(max(yaw_rate_rad_s, -max_rate_rad_s), max_rate_rad_s)
    return (yaw_rad + rate * dt_s) % (2 * math.pi), rate


def fall(body: KinematicState, on_ground: bool, dt_s: float) -> KinematicState:
    """A disarmed body: rests on the ground, or falls with gravity and horizontal drag until it lands."""
    p, v = body.position_ned_m, body.velocity_ned_mps
    if on_ground and v[2] <= 0.0:
        if p[2] == 0.0 and v[0] == 0.0 and v[1] == 0.0 and v[2] == 0.0:
            return body  # resting on the ground: nothing moves
        return KinematicState(position_ned_m=np.array([p[0], p[1], 0.0]), velocity_ned_mps=np.zeros(3))
    new_v = np.array([v[0] * math.exp(-dt_s), v[1] * math.exp(-dt_s), min(v[2] + GRAVITY_MPS2 * dt_s, 30.0)])
    new_p = p + new_v * dt_s
    if new_p[2] > 0.0:
        new_p[2] = 0.0
        new_v = np.zeros(3)
    return KinematicState(position_ned_m=new_p, velocity_ned_mps=new_v)
