"""Decoding SET_POSITION_TARGET_LOCAL_NED as PX4 does: type_mask, coordinate frame and validity.

type_mask bits say which fields to IGNORE: x,y,z (1,2,4), vx,vy,vz (8,16,32), ax,ay,az (64,128,256),
FORCE_SET (512), yaw (1024), yaw_rate (2048). MAVSDK's velocity-with-yaw setpoint is 2503 (positions,
accelerations and yaw rate ignored). Bits above 2048 are undefined; PX4 ignores them, and so does the decoder.

As PX4's receiver (mavlink_receiver.cpp) does: FORCE_SET (force instead of acceleration) is refused only when an
acceleration is used ("force not supported"), so a client that sets bit 9 with its accelerations ignored flies; a
used field holding NaN counts as not set; a setpoint that sets no position, velocity or acceleration at all is
refused ("invalid"). Every other setpoint is offboard proof of life. Whether it can be flown is the position
controller's input check: every axis needs at least one of position, velocity or acceleration, x and y come in
pairs for each of them, and every set value is finite; PX4 hovers (its failsafe setpoint) on one that fails, and
so does the mock (``OffboardSetpoint.flyable``). That leaves 7 (xy) x 7 (z) x 4 (yaw) = 196 flyable masks without
FORCE_SET and 3 x 3 x 4 = 36 with it (accelerations ignored): 232 of the 4096 defined ones.

Frames: LOCAL_NED (absolute, from the vehicle's boot position), LOCAL_OFFSET_NED (position relative to the
current position), BODY_NED and BODY_OFFSET_NED (position offset, velocity and acceleration rotated by the
current yaw; yaw itself stays absolute).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from comms.frames import body_frd_to_ned

MAV_FRAME_LOCAL_NED = 1
MAV_FRAME_LOCAL_OFFSET_NED = 7
MAV_FRAME_BODY_NED = 8
MAV_FRAME_BODY_OFFSET_NED = 9
SUPPORTED_FRAMES = (MAV_FRAME_LOCAL_NED, MAV_FRAME_LOCAL_OFFSET_NED, MAV_FRAME_BODY_NED, MAV_FRAME_BODY_OFFSET_NED)

IGNORE_X, IGNORE_Y, IGNORE_Z = 1, 2, 4
IGNORE_VX, IGNORE_VY, IGNORE_VZ = 8, 16, 32
IGNORE_AX, IGNORE_AY, IGNORE_AZ = 64, 128, 256
FORCE_SET = 512
IGNORE_YAW = 1024
IGNORE_YAW_RATE = 2048
MASK_VELOCITY_AND_YAW = 2503
DEFINED_BITS = 0x0FFF
_ACCELERATION_BITS = IGNORE_AX | IGNORE_AY | IGNORE_AZ


@dataclass(frozen=True)
class OffboardSetpoint:
    """A decoded setpoint in local NED; NaN marks what the client left to the controller.

    position_ned_m [m], velocity_ned_mps [m/s], acceleration_ned_mps2 [m/s²], yaw_rad [rad, NED],
    yaw_rate_rad_s [rad/s].
    """

    position_ned_m: tuple[float, float, float]
    velocity_ned_mps: tuple[float, float, float]
    acceleration_ned_mps2: tuple[float, float, float]
    yaw_rad: float
    yaw_rate_rad_s: float
    type_mask: int
    frame: int
    flyable: bool = True
    """Passes the position controller's input check; False: proof of life only, the vehicle hovers."""


def _pick(values: ArrayLike, mask: int, bits: tuple[int, int, int]) -> NDArray[np.float64]:
    v = np.asarray(values, dtype=float)
    return np.array([math.nan if mask & b else float(v[i]) for i, b in enumerate(bits)])


def _all_finite_where_set(*values: NDArray[np.float64] | float) -> bool:
    """No infinity among the values that are set (NaN means not set)."""
    return all(math.isnan(x) or math.isfinite(x) for v in values for x in np.atleast_1d(v))


def _axes_valid(pos: NDArray[np.float64], vel: NDArray[np.float64], acc: NDArray[np.float64]) -> str | None:
    given = [~np.isnan(pos), ~np.isnan(vel), ~np.isnan(acc)]
    for axis in range(3):
        if not (given[0][axis] or given[1][axis] or given[2][axis]):
            return "axis_without_setpoint"
    if any(g[0] != g[1] for g in given):
        return "xy_not_paired"
    return None


def decode_position_target(
    frame: int,
    type_mask: int,
    position: ArrayLike,
    velocity: ArrayLike,
    acceleration: ArrayLike,
    yaw_rad: float,
    yaw_rate_rad_s: float,
    current_position_ned_m: ArrayLike,
    current_yaw_rad: float,
) -> OffboardSetpoint | str:
    """Decode one SET_POSITION_TARGET_LOCAL_NED; returns the setpoint (maybe not flyable) or why it is refused."""
    if type_mask < 0:
        return "type_mask_out_of_range"
    type_mask &= DEFINED_BITS
    if frame not in SUPPORTED_FRAMES:
        return "frame_unsupported"
    if type_mask & FORCE_SET and (type_mask & _ACCELERATION_BITS) != _ACCELERATION_BITS:
        return "force_setpoint_unsupported"
    pos = _pick(position, type_mask, (IGNORE_X, IGNORE_Y, IGNORE_Z))
    vel = _pick(velocity, type_mask, (IGNORE_VX, IGNORE_VY, IGNORE_VZ))
    acc = _pick(acceleration, type_mask, (IGNORE_AX, IGNORE_AY, IGNORE_AZ))
    yaw = math.nan if type_mask & IGNORE_YAW else float(yaw_rad)
    yaw_rate = math.nan if type_mask & IGNORE_YAW_RATE else float(yaw_rate_rad_s)
    if np.isnan(pos).all() and np.isnan(vel).all() and np.isnan(acc).all():
        return "no_setpoint"
    flyable = _all_finite_where_set(pos, vel, acc, yaw, yaw_rate) and _axes_valid(pos, vel, acc) is None
    current = np.asarray(current_position_ned_m, dtype=float)
    if frame in (MAV_FRAME_BODY_NED, MAV_FRAME_BODY_OFFSET_NED):
        pos = body_frd_to_ned(pos, current_yaw_rad) + current
        vel = body_frd_to_ned(vel, current_yaw_rad)
        acc = body_frd_to_ned(acc, current_yaw_rad)
    elif frame == MAV_FRAME_LOCAL_OFFSET_NED:
        pos = pos + current
    return OffboardSetpoint(
        position_ned_m=(float(pos[0]), float(pos[1]), float(pos[2])),
        velocity_ned_mps=(float(vel[0]), float(vel[1]), float(vel[2])),
        acceleration_ned_mps2=(float(acc[0]), float(acc[1]), float(acc[2])),
        yaw_rad=yaw,
        yaw_rate_rad_s=yaw_rate,
        type_mask=type_mask,
        frame=frame,
        flyable=flyable,
    )


def velocity_command_ned(
    setpoint: OffboardSetpoint,
    position_ned_m: NDArray[np.float64],
    velocity_ned_mps: NDArray[np.float64],
    xy_gain_per_s: float,
    z_gain_per_s: float,
    response_time_s: float,
) -> NDArray[np.float64]:
    """The velocity PX4's position loop would ask for: P on position plus velocity feed-forward, per axis.

    Acceleration-only axes ask for the current velocity plus the acceleration over one response time.
    """
    pos = np.array(setpoint.position_ned_m)
    vel = np.array(setpoint.velocity_ned_mps)
    acc = np.array(setpoint.acceleration_ned_mps2)
    gains = np.array([xy_gain_per_s, xy_gain_per_s, z_gain_per_s])
    command = np.zeros(3)
    for axis in range(3):
        c = 0.0
        if not math.isnan(pos[axis]):
            c += gains[axis] * (pos[axis] - position_ned_m[axis])
        if not math.isnan(vel[axis]):
            c += vel[axis]
        if math.isnan(pos[axis]) and math.isnan(vel[axis]):
            c = velocity_ned_mps[axis] + acc[axis] * response_time_s
        command[axis] = c
    return command
