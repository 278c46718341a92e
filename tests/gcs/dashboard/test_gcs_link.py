"""The ground station's side of the live map, on a recording stand-in for the Zenoh hub: event-log lines go out
classified, operator requests become a standing order that is logged and repeated."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from comms.gcs_status import EventKind, MissionEvent, OperatorCommand, OperatorRequest
from comms.signing import GROUND_STATION, KEY_BYTES, MissionKey, Signer
from comms.swarm_link import wall_clock_us
from comms.keys import MissionKeys
from comms.latest_buffer import LatestValueBuffer
from comms.messages import decode, encode
from gcs.dashboard.gcs_link import GcsDashboardLink
from gcs.processes.event_log import EventLog
from gcs.processes.mission_phase import MissionPhase
from gcs.scenario import load_scenario


class RecordingHub:
    def __init__(self) -> None:
        self.puts: list[tuple[str, bytes]] = []
        self.buffers: dict[str, LatestValueBuffer] = {}

    def put(self, key: str, payload: bytes) -> None:
        self.puts.append((key, payload))

    def subscribe(self, key: str, buffer: LatestValueBuffer) -> LatestValueBuffer:
        self.buffers[key] = buffer
        return buffer


_KEY = MissionKey(bytes(range(KEY_BYTES)))


def _signed(request: OperatorRequest, key: MissionKey = _KEY) -> bytes:
    return Signer(key, GROUND_STATION).sign(encode(request), wall_clock_us())


def _link(tmp_path: Path, phase: MissionPhase = MissionPhase.MISSION
          ) -> tuple[GcsDashboardLink, RecordingHub, list[str], EventLog]:
    keys = MissionKeys("unit")
    events = EventLog(tmp_path / "events.log", lambda: 12.5)
    station = SimpleNamespace(keys=keys, events=events, phase=phase, scenario=load_scenario("circle", []),
                              mission_key=_KEY)
    hub = RecordingHub()
    sent: list[str] = []
    return GcsDashboardLink(station, hub, sent.append, 2.0), hub, sent, events  # type: ignore[arg-type]


def test_every_event_log_line_is_published_with_its_kind(tmp_path: Path) -> None:
    _, hub, _, events = _link(tmp_path)
    events("agent 5 lost: its liveliness token is gone")
    events("vehicle 2: armed, mode OFFBOARD")
    published = [decode(MissionEvent, p) for k, p in hub.puts if k == MissionKeys("unit").events]
    assert [(e.kind, e.vehicle_id, e.t_s) for e in published] == [(EventKind.AGENT_LOST, 5, 12.5),
                                                                   (EventKind.INFO, None, 12.5)]
    assert [e.seq for e in published] == [1, 2]
    events.close()


def test_an_operator_hold_stands_is_logged_and_is_what_the_station_repeats_until_resumed(tmp_path: Path) -> None:
    link, hub, sent, events = _link(tmp_path)
    requests = hub.buffers[MissionKeys("unit").operator]
    requests.put("k", _signed(OperatorRequest(seq=1, wall_s=0.0, command=OperatorCommand.HOLD, origin="here")))
    link._take_requests()
    assert sent == ["hold"] and link.command_for("start") == "hold"
    requests.put("k", b"garbage")
    requests.put("k2", _signed(OperatorRequest(seq=2, wall_s=0.0, command=OperatorCommand.RESUME, origin="here")))
    link._take_requests()
    assert sent == ["hold", "start"] and link.command_for("start") == "start"
    events.close()
    log = (tmp_path / "events.log").read_text()
    assert "operator hold requested from here: standing order hold" in log
    assert "operator resume requested from here" in log


def test_an_operator_request_not_signed_with_the_mission_key_is_dropped_and_reported(tmp_path: Path) -> None:
    link, hub, sent, events = _link(tmp_path)
    requests = hub.buffers[MissionKeys("unit").operator]
    land = OperatorRequest(seq=1, wall_s=0.0, command=OperatorCommand.LAND, origin="intruder")
    requests.put("k", encode(land))
    requests.put("k2", _signed(land, MissionKey(bytes(KEY_BYTES))))
    link._take_requests()
    assert sent == [] and link.order is None and link.refused_requests == 2
    events.close()
    log = (tmp_path / "events.log").read_text()
    assert log.count("SECURITY: operator request dropped") == 2 and "operator land requested" not in log
