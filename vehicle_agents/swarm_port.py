"""What the onboard loop needs from the swarm network, as one small interface.

The Zenoh implementation is :class:`vehicle_agents.swarm_link_zenoh.ZenohSwarmLink`; tests of the loop's logic can
use an in-memory one. Everything here is newest-value: a control step wants the latest camera frame, the latest
message of each neighbour and the latest ground-station command, never a backlog.
"""

from __future__ import annotations

from typing import Protocol

from comms.messages import CameraFrame, MissionCommand, NeighbourState


class SwarmPort(Protocol):
    def latest_frame(self) -> CameraFrame | None:
        """The newest camera frame of this vehicle (None before the first)."""
        ...

    def neighbours(self) -> list[NeighbourState]:
        """The newest message of every neighbour heard over the radio (the caller judges their age)."""
        ...

    def latest_command(self) -> MissionCommand | None:
        """The newest ground-station command addressed to this vehicle or to everyone."""
        ...

    def departed(self) -> set[int]:
        """Vehicles whose agent left (liveliness token gone): drop them at once rather than waiting for staleness."""
        ...

    def publish_state(self, state: NeighbourState) -> None:
        """Broadcast this drone's state (public key ``floodwatch/<mission>/uav/<id>/state``; the radio relays it)."""
        ...

    def close(self) -> None:
        """Withdraw the liveliness token and close the session; never raises."""
        ...
