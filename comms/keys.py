"""Zenoh key expressions: the public ones a rescue centre can subscribe to, and the internal plumbing.

Public (documented in the README; any Zenoh client can subscribe):

* ``floodwatch/<mission>/uav/<id>/state`` — each agent's ``NeighbourState`` (MessagePack), always published by
  the agent itself whether or not the radio emulator runs;
* ``floodwatch/<mission>/gcs/polygon`` — the caged flood polygon, a GeoJSON Feature (JSON);
* ``floodwatch/<mission>/gcs/vehicles`` — ``VehicleStatusReport``: every vehicle's status (MessagePack, >= 2 Hz);
* ``floodwatch/<mission>/gcs/events`` — ``MissionEvent``: the ground station's event log and alerts (and the
  ``PeerEvent`` of a ``SwarmLink.report_events`` caller, and ``SecurityEvent``: messages the ground station
  dropped for their authentication tag);
* ``floodwatch/<mission>/alive/<id>`` — liveliness tokens: a vehicle's agent (``<id>`` = vehicle id) or a service
  (``gcs``, ``radio``, ``sim``); the token disappears when the process exits or is killed.

Internal (simulation and mission plumbing):

* ``floodwatch/<mission>/sim/truth`` — ``GroundTruth`` from the simulator (feeds the radio emulator and metrics);
* ``floodwatch/<mission>/sim/uav/<id>/camera`` — ``CameraFrame`` for one vehicle's agent;
* ``floodwatch/<mission>/radio/group/<g>`` — what the radio emulator delivers to the receivers of group ``<g>``
  (``comms.radio_groups``): a ``RadioGroupBundle`` of neighbour states and, per receiver, which of them are its own
  (only those in range, after loss and delay);
* ``floodwatch/<mission>/radio/stats`` — ``RadioLinkStats`` (per-link counters);
* ``floodwatch/<mission>/uav/<id>/edge`` — ``BoundaryEdgePoints`` seen by a boundary drone;
* ``floodwatch/<mission>/gcs/command`` — ``MissionCommand`` (state-carrying, so newest-wins is right);
* ``floodwatch/<mission>/gcs/operator`` — ``OperatorRequest``: hold / resume / land-all from a dashboard;
* ``floodwatch/<mission>/sim/flood_edge`` — ``FloodEdgeTruth``: the simulated flood's true edge;
* ``floodwatch/<mission>/sim/clock`` — ``SimClockTick``: the paced simulation clock reached a control tick;
* ``floodwatch/<mission>/sim/pace/<participant>`` — ``PaceAck``: an agent (vehicle id), the cameras or the radio
  has done its part for a tick;
* ``floodwatch/<mission>/sim/pace_report`` — ``PaceReport``: real-time factor, waits, participants left behind;
* ``floodwatch/<mission>/sim/camera_stats`` — ``CameraStats``: the camera process's achieved frame rate.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

ROOT = "floodwatch"
_MISSION_RE = re.compile(r"^[A-Za-z0-9_.-]{1,64}$")
_SERVICE_RE = re.compile(r"^[A-Za-z0-9_.-]{1,64}$")


class KeyNameError(ValueError):
    """A mission or participant name that cannot be part of a key expression (wildcards, slashes, empty)."""


def validate_mission(mission: str) -> str:
    """Mission names become one key chunk: letters, digits, ``_.-`` only (no ``*``, ``$``, ``/``, ``?``, ``#``)."""
    if not _MISSION_RE.match(mission):
        raise KeyNameError(f"mission name {mission!r}: use 1-64 letters, digits, '_', '.', '-'")
    return mission


def _participant_chunk(participant: int | str) -> str:
    """A participant's name as one key chunk (a vehicle id or a service name); raises KeyNameError otherwise."""
    name = str(participant)
    if not _SERVICE_RE.match(name):
        raise KeyNameError(f"participant name {name!r}: use letters, digits, '_', '.', '-'")
    return name


@dataclass(frozen=True)
class MissionKeys:
    """Every key expression of one mission; build once, pass around (``MissionKeys("circle")``)."""

    mission: str

    def __post_init__(self) -> None:
        validate_mission(self.mission)

    @property
    def prefix(self) -> str:
        return f"{ROOT}/{self.mission}"

    # ---- public
    def state(self, vehicle_id: int) -> str:
        return f"{self.prefix}/uav/{int(vehicle_id)}/state"

    @property
    def all_states(self) -> str:
        return f"{self.prefix}/uav/*/state"

    @property
    def polygon(self) -> str:
        return f"{self.prefix}/gcs/polygon"

    def alive(self, participant: int | str) -> str:
        """Liveliness token key of a vehicle's agent (int id) or a service name (``gcs``, ``radio``, ``sim``)."""
        return f"{self.prefix}/alive/{_participant_chunk(participant)}"

    @property
    def all_alive(self) -> str:
        return f"{self.prefix}/alive/*"

    # ---- internal
    @property
    def truth(self) -> str:
        return f"{self.prefix}/sim/truth"

    def camera(self, vehicle_id: int) -> str:
        return f"{self.prefix}/sim/uav/{int(vehicle_id)}/camera"

    def ranging(self, vehicle_id: int) -> str:
        """One drone's relative-position sensor (:class:`comms.messages.NeighbourRanging`), simulated like its camera."""
        return f"{self.prefix}/sim/uav/{int(vehicle_id)}/ranging"

    @property
    def all_cameras(self) -> str:
        return f"{self.prefix}/sim/uav/*/camera"

    def inbox(self, vehicle_id: int) -> str:
        return f"{self.prefix}/radio/{int(vehicle_id)}/inbox"

    def radio_group(self, group: int) -> str:
        """What the radio emulator delivers to one group of receivers (``comms.radio_groups``)."""
        return f"{self.prefix}/radio/group/{int(group)}"

    @property
    def radio_stats(self) -> str:
        return f"{self.prefix}/radio/stats"

    def edge(self, vehicle_id: int) -> str:
        return f"{self.prefix}/uav/{int(vehicle_id)}/edge"

    @property
    def all_edges(self) -> str:
        return f"{self.prefix}/uav/*/edge"

    @property
    def command(self) -> str:
        return f"{self.prefix}/gcs/command"

    @property
    def events(self) -> str:
        return f"{self.prefix}/gcs/events"

    @property
    def vehicles(self) -> str:
        return f"{self.prefix}/gcs/vehicles"

    @property
    def operator(self) -> str:
        return f"{self.prefix}/gcs/operator"

    @property
    def flood_edge(self) -> str:
        return f"{self.prefix}/sim/flood_edge"

    @property
    def clock(self) -> str:
        return f"{self.prefix}/sim/clock"

    def pace(self, participant: int | str) -> str:
        """Where ``participant`` (a vehicle id, ``cameras`` or ``radio``) acknowledges the ticks it has done."""
        return f"{self.prefix}/sim/pace/{_participant_chunk(participant)}"

    @property
    def all_pace(self) -> str:
        return f"{self.prefix}/sim/pace/*"

    @property
    def pace_report(self) -> str:
        return f"{self.prefix}/sim/pace_report"

    @property
    def camera_stats(self) -> str:
        return f"{self.prefix}/sim/camera_stats"

    @property
    def everything(self) -> str:
        return f"{self.prefix}/**"

    # ---- parsing received keys
    def vehicle_id_of(self, key: str) -> int | None:
        """The ``<id>`` chunk of ``.../uav/<id>/...``, ``.../alive/<id>``, ``.../radio/<id>/...`` or
        ``.../sim/uav/<id>/...``; None if the key is not of this mission or the chunk is not a vehicle id."""
        if not key.startswith(self.prefix + "/"):
            return None
        parts = key[len(self.prefix) + 1 :].split("/")
        if len(parts) >= 2 and parts[0] in ("uav", "alive", "radio"):
            chunk = parts[1]
        elif len(parts) >= 3 and parts[0] == "sim" and parts[1] == "uav":
            chunk = parts[2]
        else:
            return None
        return int(chunk) if chunk.isdigit() and len(chunk) < 10 else None

    def participant_of(self, alive_key: str) -> str | None:
        """The participant name of a liveliness key (``"3"``, ``"gcs"``), None if not one of ours."""
        head = f"{self.prefix}/alive/"
        if not alive_key.startswith(head):
            return None
        name = alive_key[len(head) :]
        return name if _SERVICE_RE.match(name) else None
