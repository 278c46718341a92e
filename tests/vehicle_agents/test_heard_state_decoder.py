"""The agent's decoding of heard states: the whole decode's result and verdicts, each distinct relayed copy decoded
once (:mod:`vehicle_agents.heard_state_decoder`)."""

from __future__ import annotations

import math

import msgspec

from comms.messages import DecodeStats, NeighbourState, decode, encode
from vehicle_agents.heard_state_decoder import HeardStateDecoder


def _state(vid: int, seq: int, *, hops: int = 0, relayed: list[NeighbourState] | None = None,
           x: float = 1.0) -> NeighbourState:
    return NeighbourState(sender_id=vid, role="boundary", seq=seq, t_s=0.05 * seq, position_en_m=(x, 2.0 + vid),
                          altitude_m=10.0, velocity_en_mps=(0.5, -0.25), group="A", hops=hops,
                          edge_points_en_m=[(float(k), 3.0) for k in range(6)], extras={"ring_radius_m": 20.0},
                          lat_deg=None if vid % 2 else 52.1, lon_deg=None if vid % 2 else 4.3,
                          relayed=relayed or [])


def _carriers(seq: int) -> list[bytes]:
    """Three drones' messages, each relaying copies of the other two's previous states (as in a ring)."""
    previous = {vid: _state(vid, seq - 1) for vid in (1, 2, 3)}
    return [encode(_state(vid, seq, relayed=[msgspec.structs.replace(previous[o], hops=1, relayed=[])
                                             for o in (1, 2, 3) if o != vid]))
            for vid in (1, 2, 3)]


def test_decodes_what_the_whole_decode_gives_and_each_copy_once() -> None:
    decoder, stats, whole_stats = HeardStateDecoder(), DecodeStats(), DecodeStats()
    for seq in (5, 6, 7):
        decoder.next_poll()
        for payload in _carriers(seq):
            state = decoder.decode(payload, stats)
            assert state == decode(NeighbourState, payload, whole_stats)
            assert state is not None and encode(state) == payload
    assert stats.snapshot() == whole_stats.snapshot()
    assert decoder.copies_decoded == 9 and decoder.copies_reused == 9  # 3 new origins' copies per poll, each in 2


def test_copies_from_the_previous_poll_are_reused_and_older_ones_forgotten() -> None:
    decoder, stats = HeardStateDecoder(), DecodeStats()
    carrier = _carriers(5)[0]
    decoder.next_poll()
    decoder.decode(carrier, stats)
    decoder.next_poll()
    decoder.decode(carrier, stats)
    assert (decoder.copies_decoded, decoder.copies_reused) == (2, 2)
    decoder.next_poll()
    decoder.next_poll()
    decoder.decode(carrier, stats)
    assert (decoder.copies_decoded, decoder.copies_reused) == (4, 2)


def test_a_bad_copy_drops_its_carrier_as_the_whole_decode_does() -> None:
    good = _state(2, 4, hops=1)
    bad_copy = msgspec.msgpack.encode({**msgspec.to_builtins(good), "position_en_m": [math.nan, 1.0]})
    payload = encode(_state(1, 5, relayed=[good]))
    nan_payload = payload.replace(msgspec.msgpack.encode(good), bad_copy)
    not_relayable = payload.replace(msgspec.msgpack.encode(good), encode(_state(2, 4, hops=0)))
    truncated = payload[:-7]
    decoder = HeardStateDecoder()
    for broken in (nan_payload, not_relayable, truncated, b"\x00\x01garbage"):
        stats, whole_stats = DecodeStats(), DecodeStats()
        decoder.next_poll()
        assert decoder.decode(broken, stats) is None
        assert decode(NeighbourState, broken, whole_stats) is None
        assert stats.dropped_total() == whole_stats.dropped_total() == 1
    stats = DecodeStats()
    assert decoder.decode(payload, stats) == _state(1, 5, relayed=[good])
