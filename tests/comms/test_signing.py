"""The authentication tag (comms/signing.py) and the key file (comms/key_file.py): pure checks, no sockets."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import msgspec
import pytest

from comms.key_file import KeyFileError, create_key_file, read_key_file, write_key_file
from comms.messages import MissionCommand, NeighbourState, decode, encode
from comms.signing import (
    GROUND_STATION,
    TRAILER_BYTES,
    MissionKey,
    Rejection,
    Signer,
    Tagger,
    Verifier,
    read_block,
    sign,
    unsigned_body,
)

KEY = MissionKey(bytes(range(32)))
OTHER = MissionKey(bytes(range(1, 33)))
NOW_US = 1_800_000_000_000_000
STATE = NeighbourState(sender_id=3, role="boundary", seq=7, t_s=12.5, position_en_m=(1.0, 2.0), altitude_m=10.0)


def test_signed_state_round_trips_and_the_block_is_one_more_messagepack_object() -> None:
    body = encode(STATE)
    payload = sign(KEY, body, 3, NOW_US)
    assert len(payload) == len(body) + TRAILER_BYTES
    verdict = Verifier(KEY).check(payload, 3, NOW_US)
    assert verdict.reason is None and decode(NeighbourState, verdict.body) == STATE
    assert unsigned_body(payload) == body
    block = read_block(payload)
    assert block is not None and (block.sender, block.timestamp_us, block.body_bytes) == (3, NOW_US, len(body))
    trailer = payload[len(body):]
    assert msgspec.msgpack.decode(trailer) == trailer[2:], "the block is a MessagePack bin holding the rest"


@pytest.mark.parametrize("mutate, reason", [
    (lambda p: p[: -TRAILER_BYTES], Rejection.UNSIGNED),
    (lambda p: p[:5] + bytes([p[5] ^ 1]) + p[6:], Rejection.BAD_TAG),
    (lambda p: p[:-1] + bytes([p[-1] ^ 0x80]), Rejection.BAD_TAG),
    (lambda p: sign(OTHER, p[: -TRAILER_BYTES], 3, NOW_US), Rejection.BAD_TAG),
    (lambda p: sign(KEY, p[: -TRAILER_BYTES], 4, NOW_US), Rejection.WRONG_SENDER),
    (lambda p: sign(KEY, p[: -TRAILER_BYTES], 3, NOW_US - 31_000_000), Rejection.OUT_OF_WINDOW),
    (lambda p: sign(KEY, p[: -TRAILER_BYTES], 3, NOW_US + 31_000_000), Rejection.OUT_OF_WINDOW),
    (lambda p: b"", Rejection.UNSIGNED),
])
def test_every_kind_of_bad_payload_is_dropped_and_counted(mutate, reason: Rejection) -> None:  # noqa: ANN001
    verifier = Verifier(KEY)
    verdict = verifier.check(mutate(sign(KEY, encode(STATE), 3, NOW_US)), 3, NOW_US)
    assert verdict.body is None and verdict.reason is reason
    assert verifier.counts[reason] == 1 and verifier.dropped_total() == 1 and verifier.accepted == 0


def test_a_replay_is_refused_and_only_newer_messages_pass() -> None:
    signer, verifier = Signer(KEY, GROUND_STATION), Verifier(KEY)
    first = signer.sign(encode(MissionCommand(seq=1, t_s=1.0, command="start")), NOW_US)
    second = signer.sign(encode(MissionCommand(seq=2, t_s=1.5, command="start")), NOW_US)  # same clock reading
    assert verifier.check(first, GROUND_STATION, NOW_US).reason is None
    assert verifier.check(second, GROUND_STATION, NOW_US).reason is None, "the signer steps the timestamp itself"
    assert verifier.check(first, GROUND_STATION, NOW_US).reason is Rejection.REPLAYED
    assert verifier.check(second, GROUND_STATION, NOW_US).reason is Rejection.REPLAYED
    assert verifier.newest_us[GROUND_STATION] == NOW_US + 1


def test_senders_are_tracked_apart() -> None:
    verifier = Verifier(KEY)
    assert verifier.check(sign(KEY, encode(STATE), 3, NOW_US), 3, NOW_US).reason is None
    other = msgspec.structs.replace(STATE, sender_id=5)
    assert verifier.check(sign(KEY, encode(other), 5, NOW_US - 1000), 5, NOW_US).reason is None


def test_a_drone_cannot_sign_as_the_ground_station_on_its_own_number() -> None:
    command = sign(KEY, encode(MissionCommand(seq=9, t_s=1.0, command="land")), 4, NOW_US)
    assert Verifier(KEY).check(command, GROUND_STATION, NOW_US).reason is Rejection.WRONG_SENDER


def test_key_never_shows_in_repr_and_must_be_32_bytes() -> None:
    assert "\\x00" not in repr(KEY) and "secret" not in repr(KEY).replace("<secret>", "")
    with pytest.raises(ValueError):
        MissionKey(b"short")


def test_key_file_is_created_0600_and_read_back(tmp_path: Path) -> None:
    path = tmp_path / "plan" / "mission.key"
    key = create_key_file(path)
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    assert read_key_file(path) == key
    assert create_key_file(tmp_path / "b.key") != key, "a new key per mission"


@pytest.mark.parametrize("content, mode, message", [
    ("00" * 32, 0o644, "readable by others"),
    ("zz" * 32, 0o600, "64 hexadecimal digits"),
    ("00" * 16, 0o600, "64 hexadecimal digits"),
])
def test_bad_key_files_are_refused_with_one_line(tmp_path: Path, content: str, mode: int, message: str) -> None:
    path = tmp_path / "k"
    path.write_text(content)
    os.chmod(path, mode)
    with pytest.raises(KeyFileError, match=message):
        read_key_file(path)


def test_missing_key_file(tmp_path: Path) -> None:
    with pytest.raises(KeyFileError, match="cannot read"):
        read_key_file(tmp_path / "none")
    write_key_file(tmp_path / "k", KEY)
    assert read_key_file(tmp_path / "k") == KEY


def test_the_tag_is_rfc_2104_hmac_sha256_truncated_to_128_bits() -> None:
    import hashlib
    import hmac

    for message in (b"", b"x" * 63, b"y" * 64, b"z" * 1000):
        assert Tagger(KEY).tag(message) == hmac.digest(KEY.secret, message, hashlib.sha256)[:16]
    payload = sign(KEY, b"body", 7, NOW_US)
    assert payload[-16:] == hmac.digest(KEY.secret, payload[:-16], hashlib.sha256)[:16]
