"""Multi-machine topology on loopback: two `python -m comms.router` processes (one per "host"), clients on each."""

from __future__ import annotations

import signal
import time
from collections.abc import Callable

import pytest

from comms.keys import MissionKeys
from comms.messages import NeighbourState
from comms.swarm_link import SwarmLink
from comms.zenoh_session import ZenohConfig, ZenohOpenError, ZenohSession

pytestmark = pytest.mark.integration


def test_clients_of_two_connected_routers_exchange_states_and_liveliness(free_endpoint: Callable[[], str], spawn: Callable) -> None:
    ep_a, ep_b = free_endpoint(), free_endpoint()
    router_a = spawn("-m", "comms.router", "--listen", ep_a)
    router_b = spawn("-m", "comms.router", "--listen", ep_b, "--connect", ep_a)
    for r in (router_a, router_b):
        assert "listening on" in r.stderr.readline()
    keys = MissionKeys("rt1")
    with ZenohSession(ZenohConfig.client(ep_a)) as host_a, ZenohSession(ZenohConfig.client(ep_b)) as host_b:
        gcs = SwarmLink(host_a, keys, None, via_radio=False, participant="gcs")
        drone = SwarmLink(host_b, keys, 4, via_radio=False)
        deadline = time.monotonic() + 15
        states: list[NeighbourState] = []
        alive: set[int] = set()
        seq = 0
        while time.monotonic() < deadline and not (states and 4 in alive):
            drone.publish(NeighbourState(sender_id=4, role="leader", seq=seq, t_s=0.0, position_en_m=(1.0, 2.0), altitude_m=10.0))
            seq += 1
            update = gcs.poll()
            states += update.states
            alive.update(update.alive)
            time.sleep(0.05)
        assert states and states[-1].sender_id == 4 and 4 in alive
        host_b.close()
        dead: list[int] = []
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and 4 not in dead:
            dead += gcs.poll().dead
            time.sleep(0.05)
        assert 4 in dead
    for r in (router_a, router_b):
        r.send_signal(signal.SIGTERM)
        r.communicate(timeout=20)
        assert r.returncode == 0


def test_client_without_router_fails_clearly(free_endpoint: Callable[[], str]) -> None:
    t0 = time.monotonic()
    with pytest.raises(ZenohOpenError, match="client"):
        ZenohSession(ZenohConfig.client(free_endpoint()))
    assert time.monotonic() - t0 < 30


def test_outside_listener_sees_public_keys_of_a_running_mission(free_endpoint: Callable[[], str], spawn: Callable) -> None:
    import json

    from comms.frames import GeodeticHome
    from comms.messages import encode, flood_polygon_from_enu

    hub_ep = free_endpoint()
    keys = MissionKeys("rt2")
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        hub.declare_alive(keys.alive(3))
        listener = spawn("-m", "comms.listen", "--mission", "rt2", "--connect", hub_ep, "--duration-s", "4", "--every-s", "0")
        polygon = encode(flood_polygon_from_enu([[12, 0], [0, 12], [-12, 0], [0, -12]], GeodeticHome(), mission="rt2",
                                                t_s=5.0))
        deadline = time.monotonic() + 30.0
        seq = 0
        while listener.poll() is None and time.monotonic() < deadline:  # the listener's start-up time is the host's
            hub.put(keys.state(3), encode(NeighbourState(sender_id=3, role="boundary", seq=seq, t_s=seq * 0.05,
                                                         position_en_m=(14.0, 0.0), altitude_m=10.0, group="A")))
            hub.put(keys.polygon, polygon)
            seq += 1
            time.sleep(0.05)
        out, err = listener.communicate(timeout=30)
    assert listener.returncode == 0, err
    records = [json.loads(line) for line in out.splitlines()]
    assert {"key": keys.alive(3), "alive": True} in records
    assert any(r.get("id") == 3 and r.get("group") == "A" for r in records)
    assert any(r.get("key") == keys.polygon and r.get("vertices") == 4 and r.get("area_m2") == 288.0 for r in records)
