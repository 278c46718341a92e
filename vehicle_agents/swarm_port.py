"""What the onboard loop needs from the swarm network, as one small interface.

The Zenoh implementation is :class:`vehicle_agents.swarm_link_zenoh.ZenohSwarmLink` (built on the comms team's
``SwarmLink`` and ``NeighbourTable``). Everything here is newest-value: a control step wants the latest camera
frame, the latest message of each live neighbour and the latest ground-station command, never a backlog.
"""

from __future__ import annotations

from typing import Protocol

from comms.messages import CameraFrame, MissionCommand, NeighbourState


class SwarmPort(Protocol):
    def latest_frame(self) -> CameraFrame | None:
        """The newest camera frame of this vehicle (None before the first)."""
        ...

    def neighbours(self, now_s: float) -> list[NeighbourState]:
        """The newest message of every neighbour heard and not dead or stale at mission time ``now_s``."""
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
