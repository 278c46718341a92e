"""The agent's Zenoh side: its camera frames, the neighbours the radio delivers, ground-station commands, liveliness.

Neighbour messages come either through the radio emulator (``neighbour_source="radio"``: the simulator decides
range, loss and delay from true positions and delivers to ``radio/<id>/inbox``) or, on real hardware where the
radio itself limits range, straight from every drone's public state key (``"direct"``). Nothing else changes.
All inputs go through ``comms.zenoh_session``'s latest-value buffers, drained at each control step.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from comms.keys import MissionKeys
from comms.messages import CameraFrame, MissionCommand, NeighbourState, decode, encode
from comms.zenoh_session import ZenohConfig, ZenohSession

InboxUnpack = Callable[[str, bytes], Iterable[tuple[str, bytes]]]


class ZenohSwarmLink:
    """A :class:`~vehicle_agents.swarm_port.SwarmPort` over one Zenoh session."""

    def __init__(
        self,
        vehicle_id: int,
        mission: str,
        zenoh: ZenohConfig,
        neighbour_source: str = "radio",
        inbox_unpack: InboxUnpack | None = None,
    ) -> None:
        self.vehicle_id = vehicle_id
        self.keys = MissionKeys(mission)
        self.session = ZenohSession(zenoh)
        s, k = self.session, self.keys
        self._camera = s.subscribe(k.camera(vehicle_id))
        if neighbour_source == "radio":
            self._neighbour_buf = s.subscribe(k.inbox(vehicle_id), unpack=inbox_unpack)
        elif neighbour_source == "direct":
            self._neighbour_buf = s.subscribe(k.all_states)
        else:
            raise ValueError(f"neighbour source {neighbour_source!r}: use radio or direct")
        self._command_buf = s.subscribe(k.command)
        self._alive_buf = s.subscribe_alive(k.all_alive)
        s.declare_alive(k.alive(vehicle_id))
        self._frame: CameraFrame | None = None
        self._neighbours: dict[int, NeighbourState] = {}
        self._command: MissionCommand | None = None
        self._departed: set[int] = set()

    def latest_frame(self) -> CameraFrame | None:
        for item in self._camera.drain():
            frame = decode(CameraFrame, item.payload)
            if frame is not None and frame.vehicle_id == self.vehicle_id:
                self._frame = frame
        return self._frame

    def neighbours(self) -> list[NeighbourState]:
        for item in self._neighbour_buf.drain():
            msg = decode(NeighbourState, item.payload)
            if msg is None or msg.sender_id == self.vehicle_id:
                continue
            old = self._neighbours.get(msg.sender_id)
            if old is None or msg.seq > old.seq or msg.seq < old.seq - 1000:
                self._neighbours[msg.sender_id] = msg
        return list(self._neighbours.values())

    def latest_command(self) -> MissionCommand | None:
        for item in self._command_buf.drain():
            msg = decode(MissionCommand, item.payload)
            if msg is not None and (self._command is None or msg.seq >= self._command.seq):
                self._command = msg
        return self._command

    def departed(self) -> set[int]:
        for item in self._alive_buf.drain():
            vehicle_id = self.keys.vehicle_id_of(item.key)
            if vehicle_id is None:
                continue
            if item.kind == "delete":
                self._departed.add(vehicle_id)
                self._neighbours.pop(vehicle_id, None)
            else:
                self._departed.discard(vehicle_id)
        return self._departed

    def publish_state(self, state: NeighbourState) -> None:
        self.session.put(self.keys.state(self.vehicle_id), encode(state))

    def close(self) -> None:
        self.session.close()
