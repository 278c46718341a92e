"""SET_POSITION_TARGET_LOCAL_NED decoding: every type_mask, LOCAL_NED and BODY_NED frames."""

import itertools
import math

import numpy as np
import pytest

from mock_autopilot.setpoints import (
    MASK_VELOCITY_AND_YAW,
    MAV_FRAME_BODY_NED,
    MAV_FRAME_LOCAL_NED,
    MAV_FRAME_LOCAL_OFFSET_NED,
    OffboardSetpoint,
    decode_position_target,
    velocity_command_ned,
)

NAN3 = (math.nan,) * 3


def decode(mask: int, frame: int = MAV_FRAME_LOCAL_NED, pos=(1.0, 2.0, -3.0), vel=(0.5, -0.5, 0.1), acc=(0.0, 0.0, 0.0),
           yaw: float = 0.3, yaw_rate: float = 0.1, here=(0.0, 0.0, 0.0), yaw_now: float = 0.0):
    return decode_position_target(frame, mask, pos, vel, acc, yaw, yaw_rate, here, yaw_now)


def expected_valid(mask: int) -> bool:
    """PX4's rule written independently, bit by bit: undefined bits above 11 ignored, FORCE_SET refused only with an
    acceleration in use, then every axis set and x/y paired."""
    mask %= 4096
    ignored = [bool(mask & (1 << b)) for b in range(9)]  # x y z vx vy vz ax ay az
    if mask & 512 and not all(ignored[6:9]):
        return False
    for axis in range(3):
        if all(ignored[axis + 3 * k] for k in range(3)):
            return False
    for k in range(3):
        if ignored[3 * k] != ignored[3 * k + 1]:
            return False
    return True


def expected_proof_of_life(mask: int) -> bool:
    """PX4's receiver: no FORCE_SET with an acceleration, and at least one position, velocity or acceleration."""
    mask %= 4096
    if mask & 512 and (mask & 448) != 448:
        return False
    return (mask & 511) != 511


def test_every_mask_combination() -> None:
    decoded = {m: decode(m) for m in range(8192)}
    accepted = [m for m, d in decoded.items() if isinstance(d, OffboardSetpoint)]
    assert accepted == [m for m in range(8192) if expected_proof_of_life(m)]
    valid = [m for m in accepted if decoded[m].flyable]
    assert valid == [m for m in range(8192) if expected_valid(m)]
    assert len(valid) == 2 * (7 * 7 * 4 + 3 * 3 * 4)
    assert decode(MASK_VELOCITY_AND_YAW | 4096).type_mask == MASK_VELOCITY_AND_YAW


def test_force_set_refused_only_with_an_acceleration() -> None:
    assert isinstance(decode(MASK_VELOCITY_AND_YAW | 512), OffboardSetpoint)
    acceleration_xy = 0b1100_0011_1111  # positions, velocities, yaw and yaw rate ignored; ax ay az used
    assert isinstance(decode(acceleration_xy), OffboardSetpoint)
    assert decode(acceleration_xy | 512) == "force_setpoint_unsupported"
    assert decode((MASK_VELOCITY_AND_YAW & ~256) | 512) == "force_setpoint_unsupported"  # az used


def test_mavsdk_velocity_yaw_mask() -> None:
    sp = decode(MASK_VELOCITY_AND_YAW, pos=NAN3, vel=(1.0, 2.0, -0.5), yaw=1.2, yaw_rate=math.nan)
    assert isinstance(sp, OffboardSetpoint)
    assert np.all(np.isnan(sp.position_ned_m))
    assert sp.velocity_ned_mps == (1.0, 2.0, -0.5)
    assert sp.yaw_rad == 1.2 and math.isnan(sp.yaw_rate_rad_s)


@pytest.mark.parametrize("mask", [m for m in range(4096) if expected_valid(m)])
def test_valid_masks_keep_exactly_the_fields_not_ignored(mask: int) -> None:
    sp = decode(mask)
    assert isinstance(sp, OffboardSetpoint)
    for k, (values, given) in enumerate(((sp.position_ned_m, (1.0, 2.0, -3.0)), (sp.velocity_ned_mps, (0.5, -0.5, 0.1)), (sp.acceleration_ned_mps2, (0.0, 0.0, 0.0)))):
        for axis in range(3):
            ignored = bool(mask & (1 << (3 * k + axis)))
            assert math.isnan(values[axis]) == ignored
            if not ignored:
                assert values[axis] == given[axis]
    assert math.isnan(sp.yaw_rad) == bool(mask & 1024)
    assert math.isnan(sp.yaw_rate_rad_s) == bool(mask & 2048)


def test_nan_in_a_used_field_is_unset_and_infinity_is_not_flyable() -> None:
    assert not decode(MASK_VELOCITY_AND_YAW, vel=(math.nan, 0.0, 0.0)).flyable  # north has no setpoint left
    assert decode(MASK_VELOCITY_AND_YAW, yaw=math.nan).flyable  # yaw unset: no yaw setpoint, as PX4
    assert not decode(MASK_VELOCITY_AND_YAW, vel=(math.inf, 0.0, 0.0)).flyable
    assert decode(MASK_VELOCITY_AND_YAW, vel=NAN3) == "no_setpoint"
    assert decode(MASK_VELOCITY_AND_YAW, pos=NAN3, acc=NAN3, yaw_rate=math.nan).flyable


def test_unsupported_frames_and_force() -> None:
    assert decode(MASK_VELOCITY_AND_YAW, frame=0) == "frame_unsupported"
    assert decode(MASK_VELOCITY_AND_YAW, frame=6) == "frame_unsupported"
    assert decode(MASK_VELOCITY_AND_YAW | 512, frame=6) == "frame_unsupported"  # the frame is checked first


def test_body_ned_rotates_velocity_by_yaw() -> None:
    # Facing east (yaw 90 deg): body forward is NED east.
    sp = decode(MASK_VELOCITY_AND_YAW, frame=MAV_FRAME_BODY_NED, vel=(2.0, 0.0, 0.5), yaw_now=math.pi / 2)
    assert isinstance(sp, OffboardSetpoint)
    assert np.allclose(sp.velocity_ned_mps, (0.0, 2.0, 0.5), atol=1e-12)
    # body right at yaw 90 deg is NED south
    sp = decode(MASK_VELOCITY_AND_YAW, frame=MAV_FRAME_BODY_NED, vel=(0.0, 1.0, 0.0), yaw_now=math.pi / 2)
    assert np.allclose(sp.velocity_ned_mps, (-1.0, 0.0, 0.0), atol=1e-12)


def test_body_and_offset_positions_are_relative() -> None:
    position_only = 0b110111111000
    sp = decode(position_only, frame=MAV_FRAME_BODY_NED, pos=(1.0, 0.0, -2.0), here=(10.0, 5.0, -3.0), yaw_now=math.pi)
    assert np.allclose(sp.position_ned_m, (9.0, 5.0, -5.0))
    sp = decode(position_only, frame=MAV_FRAME_LOCAL_OFFSET_NED, pos=(1.0, 2.0, 0.0), here=(10.0, 5.0, -3.0))
    assert np.allclose(sp.position_ned_m, (11.0, 7.0, -3.0))
    sp = decode(position_only, frame=MAV_FRAME_LOCAL_NED, pos=(1.0, 2.0, -4.0), here=(10.0, 5.0, -3.0))
    assert np.allclose(sp.position_ned_m, (1.0, 2.0, -4.0))


def test_velocity_command_mixes_position_and_velocity_per_axis() -> None:
    # xy velocity, z position (a common "fly at altitude" setpoint)
    mask = (1 | 2) | (32) | (64 | 128 | 256) | 2048 | 1024
    sp = decode(mask, pos=(0.0, 0.0, -10.0), vel=(1.0, -1.0, 0.0))
    assert isinstance(sp, OffboardSetpoint)
    cmd = velocity_command_ned(sp, np.array([0.0, 0.0, -8.0]), np.zeros(3), 1.0, 0.5, 0.3)
    assert np.allclose(cmd, (1.0, -1.0, -1.0))


@pytest.mark.parametrize("frame,yaw_now", list(itertools.product([MAV_FRAME_LOCAL_NED, MAV_FRAME_BODY_NED], [0.0, 1.0, -2.5])))
def test_speed_is_preserved_by_every_frame(frame: int, yaw_now: float) -> None:
    sp = decode(MASK_VELOCITY_AND_YAW, frame=frame, vel=(3.0, 4.0, 1.0), yaw_now=yaw_now)
    assert math.hypot(*sp.velocity_ned_mps[:2]) == pytest.approx(5.0)
    assert sp.velocity_ned_mps[2] == 1.0
