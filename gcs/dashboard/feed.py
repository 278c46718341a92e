"""The dashboard's Zenoh side: a client session on the mission's public keys, decoded into the model.

Events and polygons must each be kept (a latest-value buffer would keep only the newest per key), so their
subscriptions file every sample under its own key (``<key>#<n>``); the status and the flood edge are newest-wins.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

from comms.gcs_status import FloodEdgeTruth, MissionEvent, OperatorCommand, OperatorRequest, VehicleStatusReport
from comms.key_file import KeyFileError, read_key_file
from comms.keys import MissionKeys
from comms.latest_buffer import LatestValueBuffer
from comms.messages import FloodPolygon, decode, encode
from comms.signing import GROUND_STATION, Signer
from comms.swarm_link import wall_clock_us
from comms.zenoh_session import ZenohConfig, ZenohSession
from gcs.dashboard.model import DashboardModel


def _each_sample() -> Callable[[str, bytes], Iterable[tuple[str, bytes]]]:
    counter = itertools.count()

    def unpack(key: str, payload: bytes) -> Iterable[tuple[str, bytes]]:
        return [(f"{key}#{next(counter)}", payload)]

    return unpack


class OperatorKeyMissing(RuntimeError):
    """The dashboard has no usable mission key, so it cannot sign an operator request (the message says why)."""


class DashboardFeed:
    """Subscribes on open; :meth:`apply` moves what arrived into the model; :meth:`close` ends the session."""

    def __init__(self, mission: str, config: ZenohConfig, key_file: Path | None = None) -> None:
        """Raises ``ZenohOpenError`` when the mission's hub (or router) cannot be reached. ``key_file``: the mission
        key that signs operator requests, read at the first request (the ground station writes it after starting
        its dashboard); without it the dashboard can show the mission but not command it."""
        self.key_file = key_file
        self._signer: Signer | None = None
        self.keys = MissionKeys(mission)
        self.session = ZenohSession(config)
        self.buffer = LatestValueBuffer()
        self.dropped = 0
        self._seq = 0
        self.session.subscribe(self.keys.vehicles, self.buffer)
        self.session.subscribe(self.keys.flood_edge, self.buffer)
        self.session.subscribe(self.keys.events, self.buffer, unpack=_each_sample())
        self.session.subscribe(self.keys.polygon, self.buffer, unpack=_each_sample())

    def apply(self, model: DashboardModel) -> int:
        """Decode everything pending into ``model``; returns how many messages were applied (bad ones counted in
        ``dropped``)."""
        now_wall_s = time.time()
        handlers: dict[str, tuple[type, Callable[[Any], None]]] = {
            self.keys.vehicles: (VehicleStatusReport, lambda m: model.on_vehicles(m, now_wall_s)),
            self.keys.events: (MissionEvent, lambda m: model.on_event(m, now_wall_s)),
            self.keys.polygon: (FloodPolygon, lambda m: model.on_polygon(m, now_wall_s)),
            self.keys.flood_edge: (FloodEdgeTruth, lambda m: model.on_flood_edge(m, now_wall_s)),
        }
        applied = 0
        for item in self.buffer.drain():
            handler = handlers.get(item.key.split("#", 1)[0])
            if handler is None or item.kind != "put":
                continue
            message = decode(handler[0], item.payload)
            if message is None:
                self.dropped += 1
                continue
            handler[1](message)
            applied += 1
        return applied

    def request(self, command: OperatorCommand, origin: str) -> None:
        """Ask the ground station for an operator order (the caller has checked the token), signed with the
        mission key as the ground station's own commands are; raises :class:`OperatorKeyMissing` without a key."""
        if self._signer is None:
            if self.key_file is None:
                raise OperatorKeyMissing("this dashboard has no mission key (--key-file): the ground station "
                                         "obeys only signed operator requests")
            try:
                self._signer = Signer(read_key_file(self.key_file), GROUND_STATION)
            except KeyFileError as exc:
                raise OperatorKeyMissing(str(exc)) from None
        self._seq += 1
        body = encode(OperatorRequest(seq=self._seq, wall_s=time.time(), command=command, origin=origin))
        self.session.put(self.keys.operator, self._signer.sign(body, wall_clock_us()))

    def close(self) -> None:
        self.session.close()
