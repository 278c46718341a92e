"""Re-sent setpoints recognised from their bytes: same meaning, other sequence number and time stamp."""

from __future__ import annotations

from pymavlink.dialects.v20 import common as mavlink

from mock_autopilot.repeated_setpoint import RepeatedSetpoints, setpoint_content

_VELOCITY_ONLY = 0b0000_1101_1100_0111


def _setpoint(seq: int, time_boot_ms: int, vx: float = 1.0, sysid: int = 1, compid: int = 191) -> bytes:
    encoder = mavlink.MAVLink(None, sysid, compid)
    encoder.seq = seq
    message = mavlink.MAVLink_set_position_target_local_ned_message(
        time_boot_ms, 1, 1, mavlink.MAV_FRAME_LOCAL_NED, _VELOCITY_ONLY, 0, 0, 0, vx, 0.5, 0.0, 0, 0, 0, 0.3, 0)
    return bytes(message.pack(encoder))


def test_resend_has_the_same_content_and_a_change_does_not() -> None:
    first, resent = setpoint_content(_setpoint(3, 1000)), setpoint_content(_setpoint(4, 1050))
    assert first is not None and first == resent
    assert setpoint_content(_setpoint(5, 1100, vx=1.5)) != first
    assert setpoint_content(_setpoint(5, 1100, sysid=2)) != first


def test_anything_but_one_good_setpoint_has_no_content() -> None:
    good = _setpoint(3, 1000)
    corrupted = bytearray(good)
    corrupted[20] ^= 0x01
    assert setpoint_content(bytes(corrupted)) is None
    assert setpoint_content(good + good) is None
    assert setpoint_content(good[:-1]) is None
    heartbeat = mavlink.MAVLink_heartbeat_message(6, 8, 0, 0, 4, 3).pack(mavlink.MAVLink(None, 1, 191))
    assert setpoint_content(bytes(heartbeat)) is None
    assert setpoint_content(b"") is None


def test_only_a_repeat_at_the_same_time_is_skipped() -> None:
    memo = RepeatedSetpoints()
    content = setpoint_content(_setpoint(3, 1000))
    assert not memo.repeats(content, 2.0)
    memo.handled(content, 2.0)
    assert memo.repeats(setpoint_content(_setpoint(4, 1050)), 2.0)
    assert not memo.repeats(content, 2.05)
    assert not memo.repeats(None, 2.0)
    memo.handled(None, 2.0)  # something else came in between
    assert not memo.repeats(content, 2.0)
    assert memo.skipped == 1
