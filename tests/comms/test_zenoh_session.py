"""Real Zenoh sessions on loopback: several sessions exchange, bad payloads are dropped and counted,
liveliness follows sessions, and closing leaves no thread and no hang."""

from __future__ import annotations

import asyncio
import os
import subprocess
import sys
import threading
import time
from collections.abc import Callable

import pytest

from comms.keys import MissionKeys
from comms.latest_buffer import LatestValueBuffer
from comms.messages import DecodeStats, NeighbourState, encode
from comms.radio_groups import group_inbox_key
from comms.swarm_link import SwarmLink
from comms.zenoh_session import ZenohConfig, ZenohOpenError, ZenohSession

pytestmark = pytest.mark.integration


def _state(vid: int, seq: int) -> NeighbourState:
    return NeighbourState(sender_id=vid, role="follower", seq=seq, t_s=seq * 0.05, position_en_m=(float(vid), 0.0), altitude_m=10.0)


def _until(predicate: Callable[[], bool], timeout_s: float = 10.0) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.02)
    return False


def test_several_member_peers_and_a_client_hear_each_other(free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    keys = MissionKeys("zs1")
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        members = [ZenohSession(ZenohConfig.member(hub_ep)) for _ in range(3)]
        client = ZenohSession(ZenohConfig.client(hub_ep))
        try:
            buffers = [m.subscribe(keys.all_states) for m in members] + [client.subscribe(keys.all_states)]
            time.sleep(0.5)
            seen: list[set[str]] = [set() for _ in buffers]

            def all_heard() -> bool:
                for i, m in enumerate(members):
                    m.put(keys.state(i), encode(_state(i, 1)))
                client.put(keys.state(9), encode(_state(9, 1)))
                for s, b in zip(seen, buffers):
                    s.update(r.key for r in b.drain())
                return all(len(s) == 4 for s in seen)

            assert _until(all_heard), seen
        finally:
            for s in (*members, client):
                s.close()


def test_bad_payloads_on_public_and_inbox_keys_are_dropped_and_counted(free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    keys = MissionKeys("zs2")
    stats = DecodeStats()
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub, ZenohSession(ZenohConfig.member(hub_ep)) as agent_session:
        direct = SwarmLink(hub, keys, None, via_radio=False, participant="gcs", stats=stats)
        radio = SwarmLink(agent_session, keys, 1, via_radio=True, stats=stats)
        time.sleep(0.5)
        # one key per bad payload: on a shared key newest-wins could legitimately supersede one before the poll
        for vid, payload in enumerate((b"", b"\xff" * 50, encode(_state(3, 1))[:-4], b"\x00" * 20_000), start=10):
            agent_session.put(keys.state(vid), payload)
        agent_session.put(keys.state(4), encode(_state(5, 1)))  # claims to be 5 on 4's key
        hub.put(group_inbox_key(keys, 1), b"not a bundle")
        time.sleep(0.3)
        direct.poll()
        radio.poll()
        assert stats.dropped_total() == 4
        assert stats.dropped_total("oversized") == 1 and stats.dropped_total("truncated") == 2  # empty + cut short
        assert direct.rejected_spoofed == 1
        assert agent_session.callback_errors == 1
        # still working afterwards
        agent_session.put(keys.state(3), encode(_state(3, 2)))
        got: list[NeighbourState] = []
        assert _until(lambda: bool(got.extend(direct.poll().states) or got))
        assert got[0].seq == 2


def test_liveliness_follows_sessions(free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    keys = MissionKeys("zs3")
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        gcs = SwarmLink(hub, keys, None, via_radio=False)
        agents = [ZenohSession(ZenohConfig.member(hub_ep)) for _ in range(2)]
        for i, s in enumerate(agents):
            s.declare_alive(keys.alive(i))
        alive: set[int] = set()
        assert _until(lambda: bool(alive.update(gcs.poll().alive)) or alive == {0, 1})
        assert hub.alive_now(keys.all_alive) == [keys.alive(0), keys.alive(1)]
        agents[1].close()
        dead: list[int] = []
        assert _until(lambda: bool(dead.extend(gcs.poll().dead)) or dead == [1], 5.0)
        agents[0].close()


def test_asyncio_consumer(free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    keys = MissionKeys("zs4")

    async def consume(link: SwarmLink) -> list[int]:
        got: list[int] = []
        deadline = time.monotonic() + 10
        while len(got) < 5 and time.monotonic() < deadline:
            await link.wait_async(0.5)
            got.extend(s.seq for s in link.poll().states)
        return got

    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub, ZenohSession(ZenohConfig.member(hub_ep)) as sender:
        link = SwarmLink(hub, keys, 0, via_radio=False)
        time.sleep(0.5)

        def produce() -> None:
            for seq in range(50):
                sender.put(keys.state(1), encode(_state(1, seq)))
                time.sleep(0.02)

        thread = threading.Thread(target=produce)
        thread.start()
        got = asyncio.run(consume(link))
        thread.join()
        assert len(got) >= 5 and got == sorted(got)


def test_close_leaves_no_python_thread_and_is_idempotent(free_endpoint: Callable[[], str]) -> None:
    before = set(threading.enumerate())
    hub_ep = free_endpoint()
    s1 = ZenohSession(ZenohConfig.hub(hub_ep))
    s2 = ZenohSession(ZenohConfig.member(hub_ep))
    s1.subscribe("floodwatch/x/**")
    s2.declare_alive("floodwatch/x/alive/1")
    s2.put("floodwatch/x/a", b"1")
    s1.close()
    s2.close()
    s2.close()
    assert s1.closed and s2.closed
    assert set(threading.enumerate()) <= before
    with pytest.raises(RuntimeError):
        s1.subscribe("floodwatch/x/**")


def test_process_that_forgets_to_close_exits_promptly(free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    code = (
        "from comms.zenoh_session import ZenohSession, ZenohConfig\n"
        f"s = ZenohSession(ZenohConfig.hub('{hub_ep}'))\n"
        "b = s.subscribe('floodwatch/**')\n"
        "s.declare_alive('floodwatch/t/alive/1')\n"
        "s.put('floodwatch/t/x', b'1')\n"
        "print('done', flush=True)\n"
    )
    t0 = time.monotonic()
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, cwd=str(__import__("pathlib").Path(__file__).resolve().parents[2]))
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "done"
    assert time.monotonic() - t0 < 30


def test_bad_configs_fail_with_one_clear_error(free_endpoint: Callable[[], str]) -> None:
    with pytest.raises(ValueError, match="endpoint"):
        ZenohConfig(connect=("localhost:7447",))
    with pytest.raises(ValueError, match="client"):
        ZenohConfig(mode="client")
    hub_ep = free_endpoint()
    with ZenohSession(ZenohConfig.hub(hub_ep)):
        with pytest.raises(ZenohOpenError):
            ZenohSession(ZenohConfig.hub(hub_ep))  # port already taken


def test_buffer_shared_by_two_subscribers(free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub, ZenohSession(ZenohConfig.member(hub_ep)) as other:
        buf = LatestValueBuffer()
        hub.subscribe("floodwatch/a/**", buf)
        hub.subscribe("floodwatch/b/**", buf)
        time.sleep(0.5)
        keys: set[str] = set()

        def both() -> bool:
            other.put("floodwatch/a/x", b"1")
            other.put("floodwatch/b/y", b"2")
            keys.update(r.key for r in buf.drain())
            return keys == {"floodwatch/a/x", "floodwatch/b/y"}

        assert _until(both)


def test_table_events_are_published_for_the_ground_station(free_endpoint: Callable[[], str]) -> None:
    from comms.messages import PeerEvent, decode
    from comms.neighbour_table import NeighbourTable

    hub_ep = free_endpoint()
    keys = MissionKeys("zs5")
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub, ZenohSession(ZenohConfig.member(hub_ep)) as agent:
        events_buf = hub.subscribe(keys.events, LatestValueBuffer())
        link = SwarmLink(agent, keys, 1, via_radio=False)
        time.sleep(0.5)
        table = NeighbourTable(own_id=1, period_s=0.05)
        table.heard(_state(2, 1), 0.0)
        table.expire(1.0)
        assert link.report_events(table.take_events(), observer="1") == 2
        got: list[PeerEvent] = []
        assert _until(lambda: bool(got.extend(filter(None, (decode(PeerEvent, r.payload) for r in events_buf.drain()))))
                      or any(e.event == "stale" for e in got))
        assert got[-1].vehicle_id == 2 and got[-1].event == "stale" and got[-1].observer == "1"
        assert {e.event for e in got} <= {"alive", "stale"}


def test_put_after_close_is_dropped_and_oversized_samples_are_not_buffered(free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub, ZenohSession(ZenohConfig.member(hub_ep)) as other:
        buf = hub.subscribe("floodwatch/big/**", max_payload_bytes=1000)
        time.sleep(0.5)
        other.put("floodwatch/big/a", b"x" * 1001)
        other.put("floodwatch/big/b", b"x" * 1000)
        got: set[str] = set()
        assert _until(lambda: bool(got.update(r.key for r in buf.drain())) or "floodwatch/big/b" in got)
        assert got == {"floodwatch/big/b"} and hub.oversized_samples == 1
    other.put("floodwatch/big/c", b"1")
    other.put_once("floodwatch/big/c", b"1")
    assert other.dropped_after_close == 2


_THREADS_AFTER_EXCHANGE = (
    "import os, time\n"
    "from comms.zenoh_session import ZenohSession, ZenohConfig\n"
    "hub = ZenohSession(ZenohConfig.hub('{hub}'))\n"
    "buf = hub.subscribe('floodwatch/rt/**')\n"
    "member = ZenohSession(ZenohConfig.member('{hub}'))\n"
    "deadline = time.monotonic() + 20\n"
    "while not buf.drain() and time.monotonic() < deadline:\n"
    "    member.put('floodwatch/rt/x', b'1')\n"
    "    time.sleep(0.05)\n"
    "names = sorted({{open(f'/proc/self/task/{{t}}/comm').read().strip() for t in os.listdir('/proc/self/task')}})\n"
    "print(time.monotonic() < deadline, *names, flush=True)\n"
    "member.close(); hub.close()\n"
)


def _zenoh_threads_after_exchange(hub_ep: str, env_runtime: str | None) -> list[str]:
    """Thread names of a fresh process whose two sessions exchanged a sample; fails if nothing arrived."""
    env = {k: v for k, v in os.environ.items() if k != "ZENOH_RUNTIME"}
    if env_runtime is not None:
        env["ZENOH_RUNTIME"] = env_runtime
    out = subprocess.run([sys.executable, "-c", _THREADS_AFTER_EXCHANGE.format(hub=hub_ep)], capture_output=True,
                         text=True, timeout=60, env=env, cwd=str(__import__("pathlib").Path(__file__).resolve().parents[2]))
    assert out.returncode == 0, out.stderr
    delivered, *names = out.stdout.split()
    assert delivered == "True", out.stdout
    return names


def test_sessions_run_on_the_lean_zenoh_runtime_without_shared_memory(free_endpoint: Callable[[], str]) -> None:
    names = _zenoh_threads_after_exchange(free_endpoint(), env_runtime=None)
    assert "app-0" in names, names
    assert not [n for n in names if n.split("-")[0] in ("rx", "net", "acc") or n.startswith("Watchdog")], names
    assert ("transport/shared_memory/enabled", "false") in ZenohConfig().to_json5_items()


def test_zenoh_runtime_from_the_environment_wins(free_endpoint: Callable[[], str]) -> None:
    names = _zenoh_threads_after_exchange(free_endpoint(), env_runtime="()")
    assert "rx-0" in names and "rx-1" in names, names


_OUTSIDER = """
import json, time, zenoh
c = zenoh.Config()
c.insert_json5("mode", '"client"')
c.insert_json5("connect/endpoints", json.dumps(["{hub}"]))
with zenoh.open(c) as s:
    p = s.declare_publisher("src/with")
    time.sleep(0.5)
    for n in range(20):
        p.put(b"x", source_info=zenoh.SourceInfo(p.id, n))
        s.put("src/plain", b"y")
        time.sleep(0.05)
    print(s.zid(), flush=True)
"""


def test_the_publishers_zenoh_id_and_address_when_the_sample_carries_its_source(free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        buf = hub.subscribe("src/*", with_source=True)
        out = subprocess.run([sys.executable, "-c", _OUTSIDER.format(hub=hub_ep)], capture_output=True, text=True,
                             timeout=60)
        assert out.returncode == 0, out.stderr[-2000:]
        outsider_zid = out.stdout.split()[-1]
        sources = {item.key: item.source for item in buf.drain()}
        assert sources == {"src/with": outsider_zid, "src/plain": ""}, sources
        assert hub.address_of("0" * 32) == ""


def test_a_queue_subscription_keeps_every_sample_in_order_and_drains_nothing_after_close(
        free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    keys = MissionKeys("zs9")
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        rx = ZenohSession(ZenohConfig.member(hub_ep))
        queue = rx.subscribe_queue(keys.all_states, capacity=1000)
        latest = rx.subscribe(keys.all_states)
        time.sleep(0.5)
        for seq in range(200):  # one key: a latest-value buffer keeps one sample, the queue all 200
            hub.put(keys.state(3), encode(_state(3, seq)))
        got: list[tuple[str, bytes]] = []
        assert _until(lambda: bool(got.extend(queue.drain())) or len(got) >= 200)
        assert [key for key, _ in got] == [keys.state(3)] * 200
        assert [payload for _, payload in got] == [encode(_state(3, seq)) for seq in range(200)]
        assert queue.received == 200 and len(latest.drain()) == 1
        rx.close()
        assert queue.drain() == []


def test_hot_publisher_and_declared_keys_carry_samples_and_drop_after_close(free_endpoint: Callable[[], str]) -> None:
    hub_ep = free_endpoint()
    keys = MissionKeys("zs10")
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        rx = ZenohSession(ZenohConfig.member(hub_ep))
        queue = rx.subscribe_queue(keys.all_states, capacity=100)
        rx.declare_key(keys.state(4))  # the receiver's route for this key is kept; samples arrive as before
        put = hub.publisher_of(keys.state(4))
        time.sleep(0.5)
        for seq in range(5):
            put(encode(_state(4, seq)))
        got: dict[str, bytes] = {}
        assert _until(lambda: bool(got.update(queue.drain_newest())) or queue.received >= 5)
        assert got == {keys.state(4): encode(_state(4, 4))} and queue.received == 5  # every sample taken, newest kept
        rx.close()
        rx.declare_key(keys.state(5))  # nothing after close, and no error
        hub.close()
        put(b"late")
        assert hub.dropped_after_close == 1


def test_a_blocking_publisher_waits_for_room_instead_of_dropping(free_endpoint: Callable[[], str]) -> None:
    """The radio emulator's inbox puts: Zenoh's BLOCK congestion control (a full link makes the put wait) where
    every other publisher keeps Zenoh's DROP; the first call for a key sets its mode."""
    with ZenohSession(ZenohConfig.hub(free_endpoint())) as session:
        blocking = session.publisher_of("zs/block", block=True)
        session.publisher_of("zs/drop")
        session.publisher_of("zs/block")
        modes = {key: str(publisher.congestion_control) for key, publisher in session._publishers.items()}
        assert modes == {"zs/block": "CongestionControl.BLOCK", "zs/drop": "CongestionControl.DROP"}
        blocking(b"nobody listens: nothing to wait for")
