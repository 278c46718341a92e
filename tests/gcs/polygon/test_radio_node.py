"""The ground station as a radio node: it hears only what reaches its antenna, relayed copies included, in both
engines' radios (pure; no sockets)."""

from __future__ import annotations

import numpy as np

from comms.messages import GroundTruth, NeighbourState, encode
from comms.radio_relay import RadioRelay
from comms.radio_model import GROUND_NODE_ID, RadioModel
from gcs.lockstep.radio_link import InMemoryRadio
from gcs.polygon.radio_node import ANTENNA_HEIGHT_M, GroundNode, antenna_enu_m


def _state(vid: int, x: float, seq: int = 1, t_s: float = 0.0, relayed: list | None = None) -> NeighbourState:
    return NeighbourState(sender_id=vid, role="boundary", seq=seq, t_s=t_s, position_en_m=(x, 0.0), altitude_m=10.0,
                          relayed=relayed or [])


def test_antenna_stands_on_its_mast_in_the_middle_of_the_pads() -> None:
    pads = np.array([[13.0, -1.0, 0.0], [15.0, 1.0, 0.0]])
    np.testing.assert_allclose(antenna_enu_m(pads), [14.0, 0.0, ANTENNA_HEIGHT_M])


def test_lockstep_node_hears_in_range_drones_and_what_they_relay() -> None:
    node = GroundNode(np.array([0.0, 0.0, 2.0]))
    radio = InMemoryRadio(RadioModel(range_m=15.0), [1, 2, GROUND_NODE_ID])
    positions = np.array([[8.0, 0.0, 10.0], [30.0, 0.0, 10.0]])
    far = _state(2, 30.0, seq=4)
    near = _state(1, 8.0, seq=5, relayed=[NeighbourState(sender_id=2, role="boundary", seq=3, t_s=0.0,
                                                         position_en_m=(30.0, 0.0), altitude_m=10.0, hops=1)])
    radio.broadcast(0.0, node.with_antenna(positions), [near, far, None])
    inboxes = radio.deliver(0.0)
    node.hear(inboxes[2].states, 0.0)
    assert sorted(node.heard) == [1, 2]
    assert node.heard[2].hops == 1 and node.heard[2].seq == 3  # the far drone only through the near one


def test_emulator_delivers_to_the_ground_node_and_refuses_a_sender_claiming_its_id() -> None:
    relay = RadioRelay(RadioModel(range_m=15.0), ground_node_enu_m=(0.0, 0.0, 2.0))
    relay.on_truth(GroundTruth(t_s=0.0, vehicle_ids=[1, 2], positions_enu_m=[(8.0, 0.0, 10.0), (30.0, 0.0, 10.0)]))
    relay.on_state(1, encode(_state(1, 8.0)), 0.0)
    relay.on_state(2, encode(_state(2, 30.0)), 0.0)
    assert relay.on_state(GROUND_NODE_ID, encode(_state(GROUND_NODE_ID, 0.0)), 0.0) is None
    due = relay.pop_due(1.0)
    assert [sender for sender, _ in due[GROUND_NODE_ID]] == [1]
    assert relay.counters.rejected == 1
