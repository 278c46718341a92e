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
