"""The radio emulator over real Zenoh: range gating on truth, seeded loss and latency, several processes."""

from __future__ import annotations

import json
import signal
import threading
import time
from collections.abc import Callable

import msgspec
import numpy as np
import pytest

from comms.keys import MissionKeys
from comms.latest_buffer import LatestValueBuffer
from comms.messages import GroundTruth, NeighbourState, RadioGroupBundle, RadioLinkStats, decode, encode
from comms.radio_emulator import RadioEmulator, RadioEmulatorConfig
from comms.radio_groups import group_inbox_key, selected_entries
from comms.radio_model import RadioModel
from comms.swarm_link import SwarmLink
from comms.zenoh_session import ZenohConfig, ZenohSession

pytestmark = pytest.mark.integration


def _truth(positions: np.ndarray, t_s: float = 0.0) -> bytes:
    return encode(GroundTruth(t_s=t_s, vehicle_ids=list(range(len(positions))), positions_enu_m=[tuple(map(float, p)) for p in positions]))


def _expected_sets(radio: RadioModel, positions: np.ndarray) -> dict[int, set[int]]:
    near = radio.in_range(positions)
    return {r: set(np.flatnonzero(near[:, r]).tolist()) for r in range(len(positions))}


def _state(vid: int, seq: int, claimed: tuple[float, float]) -> NeighbourState:
    return NeighbourState(sender_id=vid, role="boundary", seq=seq, t_s=seq * 0.05, position_en_m=claimed, altitude_m=10.0)


def _run_round(links: list[SwarmLink], hub: ZenohSession, keys: MissionKeys, truth: np.ndarray, rounds: int, seq0: int) -> dict[int, set[int]]:
    heard: dict[int, set[int]] = {i: set() for i in range(len(links))}
    for k in range(rounds):
        hub.put(keys.truth, _truth(truth, t_s=(seq0 + k) * 0.05))
        time.sleep(0.02)
        for i, link in enumerate(links):
            link.publish(_state(i, seq0 + k, claimed=(0.0, 0.0)))  # everyone lies: "I'm at the origin"
        time.sleep(0.05)
        for i, link in enumerate(links):
            heard[i].update(s.sender_id for s in link.poll().states if s.seq >= seq0 + 2)
    time.sleep(0.3)
    for i, link in enumerate(links):
        heard[i].update(s.sender_id for s in link.poll().states if s.seq >= seq0 + 2)
    return heard


def test_range_gating_follows_truth_as_vehicles_move(free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    keys = MissionKeys("re1")
    radio = RadioModel(range_m=25.0)
    rng = np.random.default_rng(5)
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        emulator = RadioEmulator(RadioEmulatorConfig("re1", ZenohConfig.member(hub_ep), radio))
        sessions = [ZenohSession(ZenohConfig.member(hub_ep)) for _ in range(6)]
        try:
            emulator.start()
            links = [SwarmLink(s, keys, i, via_radio=True) for i, s in enumerate(sessions)]
            time.sleep(0.8)
            first = rng.uniform(-30, 30, size=(6, 3))
            first[:, 2] = 10.0
            heard = _run_round(links, hub, keys, first, rounds=10, seq0=0)
            assert heard == _expected_sets(radio, first)
            second = first.copy()
            second[:, 0], second[:, 1] = np.arange(6) * 20.0, 0.0  # a line with 20 m gaps: only adjacent vehicles in range
            heard = _run_round(links, hub, keys, second, rounds=10, seq0=100)
            assert heard == {0: {1}, 1: {0, 2}, 2: {1, 3}, 3: {2, 4}, 4: {3, 5}, 5: {4}}
            assert emulator.relay.counters.rejected == 0
        finally:
            emulator.stop()
            for s in sessions:
                s.close()


def test_loss_and_latency_match_the_seeded_model(free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    keys = MissionKeys("re2")
    radio = RadioModel(range_m=25.0, loss_probability=0.3, latency_s=0.05, jitter_s=0.02, seed=42)
    positions = np.array([[0.0, 0.0, 10.0], [10.0, 0.0, 10.0], [0.0, 10.0, 10.0]])
    n_msgs = 200
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        emulator = RadioEmulator(RadioEmulatorConfig("re2", ZenohConfig.member(hub_ep), radio, stats_period_s=0.2))
        rx = ZenohSession(ZenohConfig.member(hub_ep))
        try:
            emulator.start()
            # one buffer entry per (receiver, sender, seq): nothing is superseded, every delivery is observed
            buffers = {}
            for r in (1, 2):
                def unpack(key: str, payload: bytes, r: int = r) -> list[tuple[str, bytes]]:
                    bundle = msgspec.msgpack.decode(payload, type=RadioGroupBundle)
                    out = []
                    for sender, data in selected_entries(bundle, r):
                        state = decode(NeighbourState, data)
                        assert state is not None
                        out.append((f"{r}/{sender}/{state.seq}", b""))
                    return out
                buffers[r] = rx.subscribe(group_inbox_key(keys, r), LatestValueBuffer(max_keys=100_000), unpack=unpack)
            stats_buf = rx.subscribe(keys.radio_stats)
            time.sleep(0.8)
            hub.put(keys.truth, _truth(positions))
            time.sleep(0.2)
            sent_at: dict[int, float] = {}
            for seq in range(n_msgs):
                sent_at[seq] = time.monotonic()
                hub.put(keys.state(0), encode(_state(0, seq, (0.0, 0.0))))
                time.sleep(0.02)
            time.sleep(0.5)
            delays = []
            for r, buf in buffers.items():
                got = {int(x.key.split("/")[2]): x.rx_monotonic_s for x in buf.drain()}
                expected, _ = radio.link_fate(0, r, np.arange(n_msgs), 0.0)
                fate = set(np.flatnonzero(expected).tolist())
                # exactly the model's fate per message; the only allowed gap is a state that never reached the
                # emulator (counted from the sender's sequence numbers; zero on an idle machine)
                assert set(got) <= fate
                assert len(fate - set(got)) <= emulator.input_gaps
                assert abs(len(got) / n_msgs - 0.7) < 0.1
                delays += [got[s] - sent_at[s] for s in got]
            d = np.array(delays)
            assert np.percentile(d, 5) >= 0.05 - 0.002  # never earlier than the latency
            assert 0.05 <= np.median(d) < 0.06 + 0.1  # ~ latency + jitter/2, plus loopback/scheduling slack on a loaded machine
            processed = n_msgs - emulator.input_gaps
            links: dict[tuple[int, int], tuple[int, int]] = {}
            deadline = time.monotonic() + 10.0
            # a report may come out between one link's delivery and the other's: wait for both to be counted
            while time.monotonic() < deadline and min(sum(links.get(link, (0, 0))) for link in ((0, 1), (0, 2))) < processed:
                stats_buf.wait(0.5)
                for x in stats_buf.drain():
                    report = decode(RadioLinkStats, x.payload)
                    assert report is not None
                    links = {(s, r): (dl, lost) for s, r, dl, lost in report.links}
            assert sum(links[(0, 1)]) == processed and sum(links[(0, 2)]) == processed
            expected, _ = radio.link_fate(0, 1, np.arange(n_msgs), 0.0)
            assert links[(0, 1)][0] <= int(expected.sum())
        finally:
            emulator.stop()
            rx.close()


def test_radio_and_agents_as_separate_processes(free_endpoint: Callable[[], str], spawn: Callable) -> None:
    hub_ep = free_endpoint()
    mission = "re3"
    keys = MissionKeys(mission)
    positions = np.array([[0.0, 0.0, 10.0], [20.0, 0.0, 10.0], [40.0, 0.0, 10.0], [40.0, 20.0, 10.0]])
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        radio_proc = spawn("-m", "comms.radio", "--mission", mission, "--range-m", "25", "--connect", hub_ep, "--duration-s", "60")
        agents = [
            spawn(str(__import__("pathlib").Path(__file__).with_name("comms_agent_proc.py")), "--hub", hub_ep, "--mission", mission,
                  "--id", str(i), "--via-radio", "--duration-s", "60", "--claim", "0", "0")
            for i in range(4)
        ]
        for a in agents:
            assert a.stdout.readline().strip() == "READY"
        stop = threading.Event()

        def publish_truth() -> None:
            while not stop.is_set():
                hub.put(keys.truth, _truth(positions, time.monotonic()))
                time.sleep(0.05)

        truth_thread = threading.Thread(target=publish_truth)
        truth_thread.start()
        try:
            time.sleep(3.0)
        finally:
            stop.set()
            truth_thread.join()
        results = {}
        for a in agents:
            a.send_signal(signal.SIGTERM)
            out, _ = a.communicate(timeout=20)
            record = json.loads(out.strip().splitlines()[-1])
            results[record["id"]] = record
        radio_proc.send_signal(signal.SIGTERM)
        _, err = radio_proc.communicate(timeout=20)
        assert radio_proc.returncode == 0, err
    heard = {i: {int(k) for k in r["heard"]} for i, r in results.items()}
    assert heard == {0: {1}, 1: {0, 2}, 2: {1, 3}, 3: {2}}
    for r in results.values():
        assert all(count >= 3 for count in r["heard"].values()), r  # a stream, not a stray message
    assert "rejected 0" in err
