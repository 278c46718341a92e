"""The agent's Zenoh side: its camera frames, the neighbours it hears, ground-station commands, liveliness.

Neighbours come through :class:`comms.swarm_link.SwarmLink`: through the radio emulator's inbox in
simulation (``via_radio=True``: range, loss and delay decided on true positions), or straight from every drone's
public state key on real hardware where the radio itself limits range (``via_radio=False``). Nothing else changes.
What arrives is handed to the onboard core as an :class:`~vehicle_agents.core.neighbours.Inbox` (states and
liveliness changes); the core keeps the table. Camera frames and commands come through latest-value buffers.
"""

from __future__ import annotations

from comms.keys import MissionKeys
from comms.messages import CameraFrame, MissionCommand, NeighbourState, NeighbourStateForControl, decode
from comms.swarm_link import SwarmLink
from comms.zenoh_session import ZenohConfig, ZenohSession
from vehicle_agents.core.neighbours import Inbox


class ZenohSwarmLink:
    """A :class:`~vehicle_agents.swarm_port.SwarmPort` over one Zenoh session."""

    def __init__(self, vehicle_id: int, mission: str, zenoh: ZenohConfig, *, via_radio: bool) -> None:
        self.vehicle_id = vehicle_id
        self.keys = MissionKeys(mission)
        self.session = ZenohSession(zenoh)
        self._camera = self.session.subscribe(self.keys.camera(vehicle_id))
        self._command_buf = self.session.subscribe(self.keys.command)
        self.link = SwarmLink(self.session, self.keys, vehicle_id, via_radio=via_radio,
                              state_type=NeighbourStateForControl)
        self._frame: CameraFrame | None = None
        self._command: MissionCommand | None = None

    def latest_frame(self) -> CameraFrame | None:
        for item in self._camera.drain():
            frame = decode(CameraFrame, item.payload)
            if frame is not None and frame.vehicle_id == self.vehicle_id:
                self._frame = frame
        return self._frame

    def take_inbox(self) -> Inbox:
        update = self.link.poll()
        return Inbox(states=update.states, departed_ids=update.dead, returned_ids=update.alive)

    def latest_command(self) -> MissionCommand | None:
        for item in self._command_buf.drain():
            msg = decode(MissionCommand, item.payload)
            if msg is not None and (self._command is None or msg.seq >= self._command.seq):
                self._command = msg
        return self._command

    def publish_state(self, state: NeighbourState) -> None:
        self.link.publish(state)

    def close(self) -> None:
        self.session.close()
