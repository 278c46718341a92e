"""What the onboard loop needs from the swarm network, as one small interface.

The Zenoh implementation is :class:`vehicle_agents.swarm_link_zenoh.ZenohSwarmLink` (built on
:class:`comms.swarm_link.SwarmLink`). A control step wants the latest camera frame and the latest ground-station
command, never a backlog; neighbour states arrive as an inbox that the onboard core files into its own table.
"""

from __future__ import annotations

from typing import Protocol

from comms.messages import CameraFrame, MissionCommand, NeighbourRanging, NeighbourState
from vehicle_agents.core.neighbours import Inbox


class SwarmPort(Protocol):
    def latest_frame(self) -> CameraFrame | None:
        """The newest camera frame of this vehicle (None before the first)."""
        ...

    def latest_ranging(self) -> NeighbourRanging | None:
        """The newest measurement of this vehicle's relative-position sensor (None before the first, or without one)."""
        ...

    def take_inbox(self) -> Inbox:
        """Every neighbour state decoded since the previous call, and whose liveliness token vanished or came back
        (the onboard core keeps the table: newest per sender, departures, timeout)."""
        ...

    def latest_command(self) -> MissionCommand | None:
        """The newest ground-station command (the caller checks whether it is addressed to it)."""
        ...

    def publish_state(self, state: NeighbourState) -> None:
        """Broadcast this drone's state (public key ``floodwatch/<mission>/uav/<id>/state``; the radio relays it)."""
        ...

    def close(self) -> None:
        """Withdraw the liveliness token and close the session; never raises."""
        ...
