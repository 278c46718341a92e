"""The live map's public messages: round trips, readable as plain MessagePack maps, bad payloads counted."""

from __future__ import annotations

import msgspec
import pytest

from comms.gcs_status import (
    EventKind,
    FloodEdgeTruth,
    LinkState,
    MissionEvent,
    OperatorCommand,
    OperatorRequest,
    VehicleStatus,
    VehicleStatusReport,
)
from comms.messages import DecodeStats, decode, encode

SAMPLES = [
    VehicleStatusReport(t_s=3.0, wall_s=1.7e9, phase="mission", flood_t_s=1.0, home_lat_deg=47.0, home_lon_deg=8.0,
                        vehicles=[VehicleStatus(vehicle_id=1, role="boundary", link=LinkState.STALE, agent_alive=True,
                                                flight_mode="OFFBOARD", armed=True, battery_fraction=0.9,
                                                lat_deg=47.0, lon_deg=8.0, altitude_m=10.0,
                                                footprint_lonlat=[(8.0, 47.0), (8.1, 47.0), (8.1, 47.1), (8.0, 47.1)],
                                                heartbeat_age_s=0.4, state_age_s=0.1)]),
    MissionEvent(seq=4, t_s=2.0, wall_s=1.7e9, kind=EventKind.AGENT_LOST, text="agent 5 lost", vehicle_id=5),
    OperatorRequest(seq=1, wall_s=1.7e9, command=OperatorCommand.HOLD, origin="127.0.0.1:4000"),
    FloodEdgeTruth(flood_t_s=2.0, ring_lonlat=[(8.0, 47.0), (8.1, 47.0), (8.1, 47.1), (8.0, 47.0)]),
]


@pytest.mark.parametrize("msg", SAMPLES, ids=lambda m: type(m).__name__)
def test_round_trip(msg: object) -> None:
    stats = DecodeStats()
    assert decode(type(msg), encode(msg), stats) == msg  # type: ignore[arg-type]
    assert stats.ok[type(msg).__name__] == 1


def test_a_client_without_our_code_reads_plain_values() -> None:
    raw = msgspec.msgpack.decode(encode(SAMPLES[0]))  # type: ignore[arg-type]
    assert raw["schema"] == "fw/vehicles/1" and raw["vehicles"][0]["link"] == "stale"
    assert msgspec.msgpack.decode(encode(SAMPLES[1]))["kind"] == "agent_lost"  # type: ignore[arg-type]


def test_an_unknown_command_or_another_version_is_dropped_and_counted() -> None:
    stats = DecodeStats()
    bad = msgspec.msgpack.encode({"schema": "fw/operator/1", "seq": 1, "wall_s": 0.0, "command": "self-destruct"})
    assert decode(OperatorRequest, bad, stats) is None
    newer = msgspec.msgpack.encode({"schema": "fw/event/2", "seq": 1, "t_s": 0.0, "wall_s": 0.0, "kind": "info",
                                    "text": "x"})
    assert decode(MissionEvent, newer, stats) is None
    assert stats.dropped == {("OperatorRequest", "malformed"): 1, ("MissionEvent", "wrong_version"): 1}
