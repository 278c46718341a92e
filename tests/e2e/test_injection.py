"""An outsider on the mission's Zenoh hub tries to command the fleet and forge states, during a real mission.

The mission runs as always (ground station, mock PX4 fleet over loopback MAVLink, cameras, radio, one agent process
per drone); the test joins the hub as an outside Zenoh client, as anyone on the host can, and tries four things:
an unsigned ``land``, a ``land`` signed with a key of its own, a replay of a genuine command it captured, and a
state for vehicle 3 signed by a key holder that is vehicle 5. Nothing may change in the flight, and each attempt
must be counted and reported (events.log and the public events key) within 1 s.
"""

from __future__ import annotations

import asyncio
import json
import os
import re
import threading
import time
from pathlib import Path

import pytest

from comms.key_file import read_key_file
from comms.keys import MissionKeys
from comms.messages import MissionCommand, NeighbourState, SecurityEvent, decode, encode
from comms.signing import GROUND_STATION, KEY_BYTES, MissionKey, Signer, unsigned_body
from comms.swarm_link import wall_clock_us
from comms.zenoh_session import ZenohConfig, ZenohSession
from gcs.processes import ProcessOptions
from gcs.processes.ground_station import GroundStation
from gcs.scenario import load_scenario

pytestmark = [pytest.mark.integration, pytest.mark.e2e, pytest.mark.slow]  # ~75 s: a whole mission

BASE = 27300
REPORT_WITHIN_S = 1.0


def _wait_for(predicate, timeout_s: float) -> float | None:  # noqa: ANN001
    """Seconds until ``predicate()`` held, or None after ``timeout_s``."""
    start = time.monotonic()
    while time.monotonic() - start < timeout_s:
        if predicate():
            return time.monotonic() - start
        time.sleep(0.01)
    return None


def test_injected_commands_and_forged_states_change_nothing_and_are_reported(tmp_path: Path) -> None:
    out = tmp_path / "run"
    out.mkdir()
    mission = f"inject{BASE}"
    hub = f"tcp/127.0.0.1:{BASE + 60}"
    options = ProcessOptions(scenario_arg="circle", mode="improved", speed=1.0, duration_s=22.0, out_dir=out,
                             mission=mission, mavlink_base_port=BASE, gcs_port=BASE + 50, zenoh_endpoint=hub,
                             live=False)
    station = GroundStation(load_scenario("circle"), options, out)
    keys = MissionKeys(mission)
    result: dict[str, int] = {}
    runner = threading.Thread(target=lambda: result.setdefault("code", asyncio.run(station.run())))
    runner.start()
    security: list[SecurityEvent] = []
    delays: dict[str, float | None] = {}
    try:
        assert _wait_for(lambda: station.phase == "mission" and station.flood_time_s() > 5.0, 180.0) is not None, \
            (out / "events.log").read_text()[-2000:]
        with ZenohSession(ZenohConfig.client(hub)) as outsider:
            commands = outsider.subscribe(keys.command)
            events = outsider.subscribe(keys.events)
            assert _wait_for(lambda: len(commands) > 0, 3.0) is not None, "no command heard from the ground station"
            captured = commands.drain()[-1].payload
            assert decode(MissionCommand, unsigned_body(captured)) is not None
            time.sleep(0.6)  # the ground station has sent a newer command since: the capture is now a replay

            def security_events() -> list[SecurityEvent]:
                for item in events.drain():
                    event = decode(SecurityEvent, item.payload)
                    if event is not None:
                        security.append(event)
                return security

            def attempt(name: str, key: str, payload: bytes, reason: str, claimed: str) -> None:
                lines_before = len(station.events.entries)
                outsider.put_once(key, payload)
                delays[name] = _wait_for(
                    lambda: any(text.startswith("SECURITY") and key in text
                                for _, text in station.events.entries[lines_before:])
                    and any(e.reason == reason and e.key == key and e.claimed_sender == claimed and e.count == 1
                            for e in security_events()), 3.0)
                time.sleep(1.2)  # past the one-second grouping of reports

            now_t_s = station.mission_t_s
            land = encode(MissionCommand(seq=10**6, t_s=now_t_s, command="land"))
            attempt("unsigned land", keys.command, land, "unsigned", "unknown")
            wrong_key = Signer(MissionKey(os.urandom(KEY_BYTES)), GROUND_STATION)
            attempt("land with a wrong key", keys.command, wrong_key.sign(land, wall_clock_us()), "bad_tag", "gcs")
            attempt("replayed command", keys.command, captured, "replayed", "gcs")
            key_holder = Signer(read_key_file(out / "plan" / "mission.key"), 5)
            forged = NeighbourState(sender_id=3, role="boundary", seq=10**6, t_s=now_t_s, position_en_m=(0.0, 0.0),
                                    altitude_m=10.0)
            attempt("state for another id", keys.state(3), key_holder.sign(encode(forged), wall_clock_us()),
                    "wrong_sender", "5")
            time.sleep(3.0)  # anything obeyed would show as a mode change by now
    finally:
        runner.join(timeout=180.0)
        if runner.is_alive():
            station.interrupt()
            runner.join(timeout=30.0)
    log = (out / "events.log").read_text()
    assert result.get("code") == 0, log[-3000:]
    assert delays and all(d is not None and d < REPORT_WITHIN_S for d in delays.values()), (delays, log[-3000:])
    assert len({(e.reason, e.key) for e in security}) >= 4, security
    under_attack = log[log.index("SECURITY"):log.index("mission complete")]
    mode_changes = re.findall(r"vehicle \d+: .*mode (?!OFFBOARD)\S+", under_attack)
    assert not mode_changes, f"a vehicle left OFFBOARD after the first attempt: {mode_changes}"
    for vid in range(1, 14):  # every agent refused the commands it saw (a newer genuine one may hide an attempt)
        refused = re.search(r"dropped for their tag: (\d+) commands", (out / f"agent_{vid}.log").read_text())
        assert refused is not None and int(refused.group(1)) >= 1, f"agent {vid} refused no command"
    assert re.search(r"rejected [1-9]", (out / "radio.log").read_text()), "the radio relayed the forged state"
    summary = json.loads((out / "metrics.json").read_text())["summary"]
    assert summary["polygon_iou_final"] >= 0.95 and summary["near_miss_pairs"] == 0, summary
    assert summary["tracking_rms_last_10s_m"] <= 1.0, summary
