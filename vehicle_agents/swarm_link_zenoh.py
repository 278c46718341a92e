"""The agent's Zenoh side: its camera frames and neighbour ranging, the neighbours it hears, ground-station commands,
liveliness.

Neighbours come through :class:`comms.swarm_link.SwarmLink`: through the radio emulator's inbox in
simulation (``via_radio=True``: range, loss and delay decided on true positions), or straight from every drone's
public state key on real hardware where the radio itself limits range (``via_radio=False``). Nothing else changes.
What arrives is handed to the onboard core as an :class:`~vehicle_agents.core.neighbours.Inbox` (states and
liveliness changes); the core keeps the table. Camera frames, the relative-position sensor's measurements (a drone
that corrects its odometry with them) and commands come through latest-value buffers.
With the mission key, states are signed and checked (:mod:`comms.signing`), and only commands the ground station
signed, newer than the last one accepted, are obeyed; the rest are dropped and counted in ``command_verifier``.
"""

from __future__ import annotations

from comms.keys import MissionKeys
from comms.messages import (
    CameraFrame,
    MissionCommand,
    NeighbourRanging,
    NeighbourState,
    NeighbourStateForControl,
    decode,
)
from comms.signing import GROUND_STATION, MissionKey, Verifier
from comms.swarm_link import SwarmLink, wall_clock_us
from comms.zenoh_session import ZenohConfig, ZenohSession
from vehicle_agents.core.neighbours import Inbox
from vehicle_agents.heard_state_decoder import HeardStateDecoder


class ZenohSwarmLink:
    """A :class:`~vehicle_agents.swarm_port.SwarmPort` over one Zenoh session."""

    def __init__(self, vehicle_id: int, mission: str, zenoh: ZenohConfig, *, via_radio: bool, key: MissionKey,
                 relays: bool = False, ranges: bool = False) -> None:
        """``relays``: this drone forwards what it hears (multi-hop), so neighbour states are decoded whole, relayed
        copies and edge points included (each distinct copy once, :mod:`vehicle_agents.heard_state_decoder`);
        otherwise only the fields the control laws read. ``ranges``: it reads its relative-position sensor."""
        self.vehicle_id = vehicle_id
        self.keys = MissionKeys(mission)
        self.session = ZenohSession(zenoh)
        self._camera = self.session.subscribe(self.keys.camera(vehicle_id))
        self._command_buf = self.session.subscribe(self.keys.command)
        self._ranging_buf = self.session.subscribe(self.keys.ranging(vehicle_id)) if ranges else None
        self.link = SwarmLink(self.session, self.keys, vehicle_id, via_radio=via_radio, key=key,
                              state_type=NeighbourState if relays else NeighbourStateForControl,
                              state_decoder=HeardStateDecoder() if relays else None)
        self.command_verifier = Verifier(key)
        self._frame: CameraFrame | None = None
        self._ranging: NeighbourRanging | None = None
        self._command: MissionCommand | None = None

    def latest_frame(self) -> CameraFrame | None:
        for item in self._camera.drain():
            frame = decode(CameraFrame, item.payload)
            if frame is not None and frame.vehicle_id == self.vehicle_id:
                self._frame = frame
        return self._frame

    def latest_ranging(self) -> NeighbourRanging | None:
        if self._ranging_buf is not None:
            for item in self._ranging_buf.drain():
                msg = decode(NeighbourRanging, item.payload)
                if msg is not None and msg.vehicle_id == self.vehicle_id:
                    self._ranging = msg
        return self._ranging

    def take_inbox(self) -> Inbox:
        update = self.link.poll()
        return Inbox(states=update.states, departed_ids=update.dead, returned_ids=update.alive)

    def latest_command(self) -> MissionCommand | None:
        now_us = wall_clock_us()
        for item in self._command_buf.drain():
            body = self.command_verifier.check(item.payload, GROUND_STATION, now_us).body
            msg = None if body is None else decode(MissionCommand, body)
            if msg is not None and (self._command is None or msg.seq >= self._command.seq):
                self._command = msg
        return self._command

    def publish_state(self, state: NeighbourState) -> None:
        self.link.publish(state)

    def close(self) -> None:
        self.session.close()
