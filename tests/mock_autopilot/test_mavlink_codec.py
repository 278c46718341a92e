"""The protocol layer bytes in / messages out: framing per datagram, CRC, ids, targets, infinities, signing."""

import hashlib
import math

import pytest
from pymavlink.dialects.v20 import common as mavlink

from mock_autopilot.mavlink_codec import LinkCodec, SigningState, parse_signing_key, signing_timestamp

NOW = 1_750_000_000.0
KEY = bytes(range(32))


def client(sysid: int = 255, compid: int = 190) -> mavlink.MAVLink:
    return mavlink.MAVLink(None, sysid, compid)


def heartbeat_frame(mav: mavlink.MAVLink | None = None) -> bytes:
    return mavlink.MAVLink_heartbeat_message(6, 8, 0, 0, 4, 3).pack(mav or client())


def command_frame(target: int = 1, comp: int = 1, mav: mavlink.MAVLink | None = None, p1: float = 1.0) -> bytes:
    return mavlink.MAVLink_command_long_message(target, comp, 400, 0, p1, 0, 0, 0, 0, 0, 0).pack(mav or client())


def test_valid_frame_is_decoded_and_vouches() -> None:
    codec = LinkCodec(1)
    parsed = codec.parse_datagram(command_frame(), NOW)
    assert [m.get_type() for m in parsed.messages] == ["COMMAND_LONG"]
    assert parsed.vouched
    assert not codec.drops


def test_several_frames_in_one_datagram() -> None:
    codec = LinkCodec(1)
    parsed = codec.parse_datagram(heartbeat_frame() + command_frame() + heartbeat_frame(), NOW)
    assert [m.get_type() for m in parsed.messages] == ["HEARTBEAT", "COMMAND_LONG", "HEARTBEAT"]


def test_garbage_then_frame_in_same_datagram_still_finds_the_frame() -> None:
    codec = LinkCodec(1)
    garbage = bytes([0xFD, 0x40, 0, 0, 0, 1, 1, 0, 0, 0]) + b"\x00\xfd\x12junk"
    parsed = codec.parse_datagram(garbage + command_frame(), NOW)
    assert [m.get_type() for m in parsed.messages] == ["COMMAND_LONG"]
    assert sum(codec.drops.values()) >= 1


def test_truncated_frame_never_swallows_the_next_datagram() -> None:
    codec = LinkCodec(1)
    frame = command_frame()
    first = codec.parse_datagram(frame[:-5], NOW)
    second = codec.parse_datagram(frame, NOW)
    assert first.messages == [] and not first.vouched
    assert [m.get_type() for m in second.messages] == ["COMMAND_LONG"]
    assert codec.drops["truncated"] >= 1


def test_bad_crc_dropped() -> None:
    codec = LinkCodec(1)
    frame = bytearray(command_frame())
    frame[-1] ^= 0xFF
    assert codec.parse_datagram(bytes(frame), NOW).messages == []
    assert codec.drops["bad_crc"] == 1


def test_mavlink1_frame_dropped_and_counted() -> None:
    mav = client()
    mav.WIRE_PROTOCOL_VERSION = "1.0"
    frame = mavlink.MAVLink_heartbeat_message(6, 8, 0, 0, 4, 3).pack(mav, force_mavlink1=True)
    assert frame[0] == 0xFE
    codec = LinkCodec(1)
    assert codec.parse_datagram(frame, NOW).messages == []
    assert codec.drops["mavlink1"] == 1


def test_unknown_message_id_is_malformed_not_unknown_n() -> None:
    frame = bytearray(command_frame())
    frame[7], frame[8], frame[9] = 0x39, 0x30, 0x00  # msg id 12345: no CRC_EXTRA known
    codec = LinkCodec(1)
    assert codec.parse_datagram(bytes(frame), NOW).messages == []
    assert codec.drops["unknown_msgid"] == 1


@pytest.mark.parametrize("target,comp,reason", [(2, 1, "wrong_target_system"), (0, 1, "wrong_target_system"), (1, 5, "wrong_target_component")])
def test_wrong_target_dropped(target: int, comp: int, reason: str) -> None:
    codec = LinkCodec(1)
    parsed = codec.parse_datagram(command_frame(target, comp), NOW)
    assert parsed.messages == [] and not parsed.vouched
    assert codec.drops[reason] == 1


def test_ping_broadcast_target_accepted() -> None:
    frame = mavlink.MAVLink_ping_message(123, 7, 0, 0).pack(client())
    assert [m.get_type() for m in LinkCodec(1).parse_datagram(frame, NOW).messages] == ["PING"]


def test_infinity_dropped_nan_passed_to_vehicle() -> None:
    codec = LinkCodec(1)
    assert codec.parse_datagram(command_frame(p1=math.inf), NOW).messages == []
    assert codec.drops["infinite_field"] == 1
    assert len(codec.parse_datagram(command_frame(p1=math.nan), NOW).messages) == 1


def test_own_frames_looped_back_are_dropped_but_companion_with_same_sysid_is_not() -> None:
    codec = LinkCodec(1)
    assert codec.parse_datagram(heartbeat_frame(client(1, 1)), NOW).messages == []
    assert codec.drops["looped_back"] == 1
    assert len(codec.parse_datagram(heartbeat_frame(client(1, 191)), NOW).messages) == 1


def test_random_bytes_never_raise() -> None:
    rng = __import__("random").Random(7)
    codec = LinkCodec(1)
    for _ in range(3000):
        data = bytes(rng.getrandbits(8) for _ in range(rng.randint(0, 300)))
        codec.parse_datagram(data, NOW)
    assert codec.frames_accepted == 0


def test_outgoing_sequence_numbers_increase() -> None:
    codec = LinkCodec(3)
    decoder = mavlink.MAVLink(None, 0, 0)
    seqs = []
    for _ in range(3):
        msg = decoder.decode(bytearray(codec.encode(mavlink.MAVLink_heartbeat_message(2, 12, 0, 0, 3, 3), NOW)))
        seqs.append(msg.get_seq())
        assert msg.get_srcSystem() == 3 and msg.get_srcComponent() == 1
    assert seqs == [0, 1, 2]


# ------------------------------------------------------------------ signing
def signed_client(link_id: int = 0, key: bytes = KEY, timestamp: int | None = None) -> mavlink.MAVLink:
    mav = client()
    mav.signing.secret_key = key
    mav.signing.sign_outgoing = True
    mav.signing.link_id = link_id
    mav.signing.timestamp = timestamp if timestamp is not None else signing_timestamp(NOW)
    return mav


def test_signing_required_rejects_unsigned_and_badly_signed() -> None:
    codec = LinkCodec(1, 1, SigningState(KEY, required=True))
    assert codec.parse_datagram(command_frame(), NOW).messages == []
    assert codec.drops["unsigned"] == 1
    bad = signed_client(key=bytes(32))
    assert codec.parse_datagram(command_frame(mav=bad), NOW).messages == []
    assert codec.drops["bad_signature"] == 1
    good = signed_client()
    parsed = codec.parse_datagram(command_frame(mav=good), NOW)
    assert [m.get_type() for m in parsed.messages] == ["COMMAND_LONG"] and parsed.vouched


def test_signing_rejects_replay_and_stale_timestamps() -> None:
    codec = LinkCodec(1, 1, SigningState(KEY, required=True))
    mav = signed_client()
    frame = command_frame(mav=mav)
    assert len(codec.parse_datagram(frame, NOW).messages) == 1
    assert codec.parse_datagram(frame, NOW).messages == []
    assert codec.drops["replayed_signature"] == 1
    old = signed_client(link_id=3, timestamp=signing_timestamp(NOW - 3600))
    assert codec.parse_datagram(command_frame(mav=old), NOW).messages == []
    assert codec.drops["stale_signature"] == 1


def test_unsigned_heartbeat_accepted_but_does_not_vouch() -> None:
    codec = LinkCodec(1, 1, SigningState(KEY, required=True))
    parsed = codec.parse_datagram(heartbeat_frame(), NOW)
    assert len(parsed.messages) == 1 and not parsed.vouched


def test_outgoing_frames_are_signed_with_the_key() -> None:
    codec = LinkCodec(1, 1, SigningState(KEY, required=True))
    data = codec.encode(mavlink.MAVLink_heartbeat_message(2, 12, 0, 0, 3, 3), NOW)
    assert data[2] & 1
    assert hashlib.sha256(KEY + data[:-6]).digest()[:6] == data[-6:]


def test_parse_signing_key() -> None:
    assert parse_signing_key(KEY.hex()) == KEY
    for bad in ("zz", "00" * 31, ""):
        with pytest.raises(ValueError):
            parse_signing_key(bad)
