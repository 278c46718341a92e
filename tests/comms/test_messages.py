"""Schemas: round trips for every kind, and bad payloads dropped and counted by reason, never raised."""

from __future__ import annotations

import random

import msgspec
import numpy as np
import pytest

from comms.frames import GeodeticHome, geodetic_to_enu
from comms.messages import (
    FLAG_AIRBORNE,
    FLAG_HAS_GPS,
    MAX_PAYLOAD_BYTES,
    BoundaryEdgePoints,
    CameraFrame,
    DecodeStats,
    FloodPolygon,
    GroundTruth,
    MissionCommand,
    NeighbourState,
    NeighbourStateForControl,
    PeerEvent,
    RadioLinkStats,
    decode,
    decode_with_reason,
    encode,
    flood_polygon_from_enu,
)


def _state(**kw: object) -> NeighbourState:
    base = dict(sender_id=4, role="boundary", seq=17, t_s=12.25, position_en_m=(14.0, -2.5), altitude_m=10.0,
                velocity_en_mps=(0.5, 1.0), lat_deg=47.4, lon_deg=8.5, flags=FLAG_AIRBORNE | FLAG_HAS_GPS,
                battery_fraction=0.8, group="B", encircle_complete=True, edge_points_en_m=[(13.0, -2.0), (13.5, -1.0)],
                extras={"gap_m": 3.5})
    base.update(kw)
    return NeighbourState(**base)  # type: ignore[arg-type]


SAMPLES = [
    _state(),
    NeighbourState(sender_id=0, role="follower", seq=0, t_s=0.0, position_en_m=(0.0, 0.0), altitude_m=10.0),
    CameraFrame(vehicle_id=2, seq=5, t_s=3.0, altitude_m=10.0, yaw_ned_rad=0.3, fov_deg=60.0, width_px=2,
                height_px=2, encoding="raw_bgr", image=bytes(range(12))),
    BoundaryEdgePoints(sender_id=1, seq=2, t_s=1.0, points_en_m=[(1.0, 2.0), (3.0, 4.0)]),
    GroundTruth(t_s=2.0, vehicle_ids=[1, 2], positions_enu_m=[(1.0, 2.0, 10.0), (3.0, 4.0, 10.0)],
                velocities_enu_mps=[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0)], yaw_ned_rad=[0.0, 1.0], alive=[True, False]),
    MissionCommand(seq=1, t_s=5.0, command="start", phase="caging", flood_clock_start_t_s=5.0, target_ids=[1]),
    RadioLinkStats(t_s=1.0, messages_in=10, delivered=8, lost=1, out_of_range=3, rejected=0, links=[(1, 2, 8, 1)]),
    PeerEvent(t_s=1.0, vehicle_id=3, event="dead", observer="gcs"),
    flood_polygon_from_enu([[12, 0], [0, 12], [-12, 0], [0, -12]], GeodeticHome(), mission="m", t_s=3.0),
]


@pytest.mark.parametrize("msg", SAMPLES, ids=lambda m: type(m).__name__)
def test_round_trip(msg: object) -> None:
    stats = DecodeStats()
    payload = encode(msg)  # type: ignore[arg-type]
    assert decode(type(msg), payload, stats) == msg
    assert decode(type(msg).__name__, payload, stats) == msg
    assert stats.ok[type(msg).__name__] == 2 and stats.dropped_total() == 0


def test_neighbour_state_is_compact_and_readable_without_our_code() -> None:
    minimal = NeighbourState(sender_id=3, role="leader", seq=9, t_s=1.0, position_en_m=(1.0, 2.0), altitude_m=10.0)
    assert len(encode(minimal)) < 120
    raw = msgspec.msgpack.decode(encode(_state()))
    assert raw["schema"] == "fw/state/1" and raw["sender_id"] == 4 and raw["group"] == "B"


def test_flood_polygon_is_rfc7946_counter_clockwise_lon_lat() -> None:
    home = GeodeticHome()
    clockwise = [[0, 10], [10, 0], [0, -10], [-10, 0]]
    poly = flood_polygon_from_enu(clockwise, home, mission="m", t_s=1.0)
    doc = msgspec.json.decode(encode(poly))
    assert doc["type"] == "Feature" and doc["geometry"]["type"] == "Polygon"
    ring = np.array(doc["geometry"]["coordinates"][0])
    assert (ring[0] == ring[-1]).all() and len(ring) == 5
    back = geodetic_to_enu(ring[:, 1], ring[:, 0], home.alt_m, home)[:, :2]
    x, y = back[:-1, 0], back[:-1, 1]
    assert 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0  # CCW
    assert doc["properties"]["area_m2"] == pytest.approx(200.0)


def test_truncated_payloads_are_counted() -> None:
    stats = DecodeStats()
    payload = encode(_state())
    for cut in range(1, len(payload)):
        assert decode(NeighbourState, payload[:cut], stats) is None
    assert stats.dropped_total() == len(payload) - 1
    assert stats.dropped_total("truncated") > 0.8 * (len(payload) - 1)


def test_random_bytes_never_raise() -> None:
    stats = DecodeStats()
    rng = random.Random(1)
    kinds = [NeighbourState, CameraFrame, GroundTruth, MissionCommand, FloodPolygon, BoundaryEdgePoints]
    for _ in range(3000):
        blob = bytes(rng.getrandbits(8) for _ in range(rng.randint(0, 64)))
        for kind in kinds:
            assert decode(kind, blob, stats) is None
    assert stats.dropped_total() == 3000 * len(kinds)


def test_oversized_is_dropped_before_parsing() -> None:
    stats = DecodeStats()
    blob = b"\x00" * (MAX_PAYLOAD_BYTES[NeighbourState] + 1)
    assert decode_with_reason(NeighbourState, blob, stats) == (None, "oversized")


def test_wrong_version_is_distinguished() -> None:
    raw = msgspec.msgpack.decode(encode(_state()))
    raw["schema"] = "fw/state/2"
    assert decode_with_reason(NeighbourState, msgspec.msgpack.encode(raw), DecodeStats()) == (None, "wrong_version")
    # another family on this key is not a version problem, just the wrong message
    assert decode_with_reason(NeighbourState, encode(SAMPLES[3]), DecodeStats())[1] == "malformed"
    poly = encode(SAMPLES[-1]).replace(b"fw/polygon/1", b"fw/polygon/7")
    assert decode_with_reason(FloodPolygon, poly, DecodeStats()) == (None, "wrong_version")


@pytest.mark.parametrize(
    "patch",
    [{"position_en_m": [float("nan"), 0.0]}, {"t_s": float("inf")}, {"sender_id": -3},
     {"edge_points_en_m": [[0.0, float("nan")]]}, {"lat_deg": float("nan")}, {"battery_fraction": float("inf")},
     {"extras": {"gap_m": float("nan")}}],
)
def test_non_finite_or_negative_fields_are_invalid(patch: dict) -> None:
    raw = msgspec.msgpack.decode(encode(_state()))
    raw.update(patch)
    assert decode_with_reason(NeighbourState, msgspec.msgpack.encode(raw), DecodeStats()) == (None, "invalid")


@pytest.mark.parametrize(
    "patch", [{"role": "pilot"}, {"position_en_m": [1.0]}, {"seq": "x"}, {"group": "C"}, {"sender_id": None}],
)
def test_wrong_types_are_malformed(patch: dict) -> None:
    raw = msgspec.msgpack.decode(encode(_state()))
    raw.update(patch)
    assert decode_with_reason(NeighbourState, msgspec.msgpack.encode(raw), DecodeStats()) == (None, "malformed")


def test_too_many_edge_points_rejected() -> None:
    raw = msgspec.msgpack.decode(encode(_state()))
    raw["edge_points_en_m"] = [[0.0, 0.0]] * 257
    assert decode(NeighbourState, msgspec.msgpack.encode(raw), DecodeStats()) is None


def test_truth_consistency_checks_and_nan_for_dead() -> None:
    truth = SAMPLES[4]
    assert isinstance(truth, GroundTruth)
    p = truth.positions_array()
    assert p.shape == (2, 3) and np.isnan(p[1]).all() and p[0].tolist() == [1.0, 2.0, 10.0]
    raw = msgspec.msgpack.decode(encode(truth))
    raw["alive"] = [True]
    assert decode_with_reason(GroundTruth, msgspec.msgpack.encode(raw), DecodeStats()) == (None, "invalid")


def test_raw_camera_size_checked() -> None:
    raw = msgspec.msgpack.decode(encode(SAMPLES[2]))
    raw["image"] = b"\x00" * 5
    assert decode_with_reason(CameraFrame, msgspec.msgpack.encode(raw), DecodeStats()) == (None, "invalid")


def test_unknown_kind_is_counted_not_raised() -> None:
    stats = DecodeStats()
    assert decode("NoSuchMessage", b"\x80", stats) is None
    assert stats.dropped_total("malformed") == 1


def test_flood_polygon_with_unknown_growth_rate_still_decodes() -> None:
    # the ground station's first polygon has no growth rate yet (NaN); JSON has no NaN, so it must go out as null
    poly = flood_polygon_from_enu([[12, 0], [0, 12], [-12, 0]], GeodeticHome(), mission="m", t_s=1.0,
                                  growth_rate_m2_per_s=float("nan"))
    back = decode(FloodPolygon, encode(poly), DecodeStats())
    assert back is not None and back.properties.growth_rate_m2_per_s is None
    with pytest.raises(ValueError):
        flood_polygon_from_enu([[np.nan, 0], [0, 12], [-12, 0]], GeodeticHome(), mission="m", t_s=1.0)
    with pytest.raises(ValueError):
        flood_polygon_from_enu([[1, 0], [0, 1], [-1, 0]], GeodeticHome(), mission="m", t_s=float("inf"))


def test_control_part_of_a_state_reads_the_same_fields_from_the_same_bytes() -> None:
    """An agent decodes only what its control laws read; every field it keeps equals the whole message's."""
    state = _state(edge_points_en_m=[(float(k), -float(k)) for k in range(24)], yaw_ned_rad=0.25,
                   velocity_up_mps=-0.5)
    payload = encode(state)
    part = decode(NeighbourStateForControl, payload, DecodeStats())
    assert part is not None
    for name in NeighbourStateForControl.__struct_fields__:
        assert getattr(part, name) == getattr(state, name), name
    assert part.has(FLAG_AIRBORNE) and not hasattr(part, "edge_points_en_m")


@pytest.mark.parametrize("bad", [{"position_en_m": (float("nan"), 0.0)}, {"t_s": float("inf")}, {"seq": -1},
                                 {"extras": {"gap_m": float("nan")}}, {"role": "tractor"}])
def test_control_part_rejects_what_the_whole_message_rejects_in_its_fields(bad: dict[str, object]) -> None:
    raw = msgspec.structs.asdict(_state())
    raw.update(bad, schema="fw/state/1")
    payload = msgspec.msgpack.encode(raw)
    stats = DecodeStats()
    assert decode(NeighbourState, payload, stats) is None
    assert decode(NeighbourStateForControl, payload, stats) is None
    assert stats.dropped_total() == 2


def test_control_part_refuses_other_schema_versions() -> None:
    raw = msgspec.structs.asdict(_state())
    raw["schema"] = "fw/state/2"
    _, reason = decode_with_reason(NeighbourStateForControl, msgspec.msgpack.encode(raw), DecodeStats())
    assert reason == "wrong_version"
