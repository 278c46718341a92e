"""The ground station's radio node in the processes engine: what the radio emulator delivers to the antenna.

The emulator (``python -m comms.radio --ground-node``) delivers to receiver 0 (on the group key ``radio/group/0``)
the states that reached the antenna at the launch site; each is checked against the mission key like every state the station hears, then filed
by :class:`~gcs.polygon.radio_node.GroundNode`, whose table the caged polygon is built from.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from comms.keys import MissionKeys
from comms.latest_buffer import LatestValueBuffer
from comms.messages import NeighbourState, decode
from comms.radio_groups import group_inbox_key
from comms.radio_model import GROUND_NODE_ID
from comms.signing import MissionKey, Verifier
from comms.swarm_link import bundle_unpacker, wall_clock_us
from comms.zenoh_session import ZenohSession
from gcs.polygon.radio_node import GroundNode, antenna_enu_m
from gcs.scenario import Scenario


class GroundRadio:
    """Subscribes to the ground node's inbox; :meth:`poll` once per loop files what arrived."""

    def __init__(self, hub: ZenohSession, keys: MissionKeys, key: MissionKey, node: GroundNode) -> None:
        self.node = node
        self._keys = keys
        self._verifier = Verifier(key)
        self._buffer = hub.subscribe(group_inbox_key(keys, GROUND_NODE_ID), LatestValueBuffer(),
                                     unpack=bundle_unpacker(keys, GROUND_NODE_ID))

    @classmethod
    def for_scenario(cls, scenario: Scenario, hub: ZenohSession, keys: MissionKeys,
                     key: MissionKey) -> GroundRadio | None:
        """The node at the launch site, or None when the scenario keeps the station outside the radio
        (``radio.gcs_lossless``)."""
        if scenario.radio.gcs_lossless:
            return None
        pads = np.array([v.pad_enu_m for v in scenario.vehicles], dtype=float)
        return cls(hub, keys, key, GroundNode(antenna_enu_m(pads), scenario.control_rate_hz))

    @property
    def heard(self) -> Mapping[int, NeighbourState]:
        return self.node.heard

    def poll(self, mission_t_s: float) -> None:
        """Verify and file every state delivered since the last call (forged or replayed ones are dropped)."""
        now_us = wall_clock_us()
        states = []
        for item in self._buffer.drain():
            if item.kind != "put":
                continue
            body = self._verifier.check(item.payload, self._keys.vehicle_id_of(item.key), now_us).body
            state = None if body is None else decode(NeighbourState, body)
            if state is not None:
                states.append(state)
        self.node.hear(states, mission_t_s)
