"""The ground station's MAVLink GCS link (UDP 14550 by default), as QGroundControl holds it.

Every PX4 sends its GCS stream to this port. The watcher logs every frame to one ``vehicle_<sysid>.tlog`` per
vehicle (8-byte big-endian microseconds since the epoch before each frame: the format ``mavlogdump.py`` reads),
keeps a small status per vehicle for the live view (mode, armed, altitude, battery, heartbeat age), reports
STATUSTEXTs and mode changes as events, and sends a GCS heartbeat back to each vehicle at 1 Hz like a real GCS.
"""

from __future__ import annotations

import asyncio
import os
import struct
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, BinaryIO

from comms.px4 import is_armed, landed_state_name, mode_name, split_frames

os.environ.setdefault("MAVLINK20", "1")
from pymavlink.dialects.v20 import common as mavlink2  # noqa: E402  (MAVLINK20 must be set first)

_DECODED_IDS = {
    mavlink2.MAVLINK_MSG_ID_HEARTBEAT,
    mavlink2.MAVLINK_MSG_ID_SYS_STATUS,
    mavlink2.MAVLINK_MSG_ID_LOCAL_POSITION_NED,
    mavlink2.MAVLINK_MSG_ID_EXTENDED_SYS_STATE,
    mavlink2.MAVLINK_MSG_ID_STATUSTEXT,
}
_DECODE_PERIOD_S = 0.2
"""Telemetry for the view is decoded at most 5 times a second per vehicle and message; every frame is logged."""
_TLOG_FLUSH_PERIOD_S = 1.0
_GCS_SYSTEM_ID = 255


@dataclass
class VehicleWatch:
    """What the ground station knows about one vehicle from its MAVLink stream."""

    system_id: int
    mode: str = "?"
    armed: bool = False
    system_status: int = 0
    altitude_m: float = float("nan")
    battery_fraction: float = float("nan")
    landed_state: str = "unknown"
    last_heartbeat_monotonic_s: float = 0.0
    frames: int = 0
    _last_decode_s: dict[int, float] = field(default_factory=dict)

    def heartbeat_age_s(self, now_monotonic_s: float) -> float:
        return now_monotonic_s - self.last_heartbeat_monotonic_s if self.last_heartbeat_monotonic_s else float("inf")


EventSink = Callable[[str], None]


class MavlinkWatcher(asyncio.DatagramProtocol):
    """asyncio UDP endpoint on the GCS port; call :meth:`open` then :meth:`close`."""

    def __init__(self, tlog_dir: Path, on_event: EventSink) -> None:
        self.vehicles: dict[int, VehicleWatch] = {}
        self.garbage_bytes = 0
        self.undecodable_frames = 0
        self._tlog_dir = tlog_dir
        self._tlogs: dict[int, BinaryIO] = {}
        self._addresses: dict[int, tuple[str, int]] = {}
        self._on_event = on_event
        self._mav = mavlink2.MAVLink(None, srcSystem=_GCS_SYSTEM_ID, srcComponent=mavlink2.MAV_COMP_ID_MISSIONPLANNER)
        self._transport: asyncio.DatagramTransport | None = None
        self._tasks: list[asyncio.Task[None]] = []
        self.failsafes: list[str] = []
        """``vehicle <id>: <text>`` for every STATUSTEXT announcing a failsafe, as PX4 does when one triggers."""

    async def open(self, host: str, port: int) -> None:
        """Bind the GCS port; raises OSError (port in use) with the port in the message."""
        loop = asyncio.get_running_loop()
        try:
            transport, _ = await loop.create_datagram_endpoint(lambda: self, local_addr=(host, port))
        except OSError as exc:
            raise OSError(exc.errno, f"GCS MAVLink port {host}:{port} is not free ({exc.strerror})") from exc
        self._transport = transport  # type: ignore[assignment]
        self._tasks = [asyncio.create_task(self._flush_loop()), asyncio.create_task(self._heartbeat_loop())]

    def datagram_received(self, data: bytes, addr: tuple[str, int]) -> None:
        frames, skipped = split_frames(data)
        self.garbage_bytes += skipped
        stamp = struct.pack(">Q", int(time.time() * 1e6))
        now_s = time.monotonic()
        for header in frames:
            vehicle = self.vehicles.get(header.system_id)
            if vehicle is None:
                vehicle = self.vehicles[header.system_id] = VehicleWatch(header.system_id)
                self._on_event(f"vehicle {header.system_id}: first MAVLink frame on the GCS link from {addr[0]}:{addr[1]}")
            self._addresses[header.system_id] = addr
            vehicle.frames += 1
            self._tlog(header.system_id).write(stamp + header.frame)
            if header.message_id in _DECODED_IDS:
                self._maybe_decode(vehicle, header.message_id, header.frame, now_s)

    def _tlog(self, system_id: int) -> BinaryIO:
        log = self._tlogs.get(system_id)
        if log is None:
            log = self._tlogs[system_id] = open(self._tlog_dir / f"vehicle_{system_id}.tlog", "ab")  # noqa: SIM115
        return log

    def _maybe_decode(self, vehicle: VehicleWatch, message_id: int, frame: bytes, now_s: float) -> None:
        always = message_id in (mavlink2.MAVLINK_MSG_ID_HEARTBEAT, mavlink2.MAVLINK_MSG_ID_STATUSTEXT)
        if not always and now_s - vehicle._last_decode_s.get(message_id, 0.0) < _DECODE_PERIOD_S:
            return
        vehicle._last_decode_s[message_id] = now_s
        try:
            msg = self._mav.decode(bytearray(frame))
        except Exception:  # noqa: BLE001 - pymavlink raises several types on bad frames; count and drop
            self.undecodable_frames += 1
            return
        self._apply(vehicle, msg, now_s)

    def _apply(self, vehicle: VehicleWatch, msg: Any, now_s: float) -> None:
        kind = msg.get_type()
        if kind == "HEARTBEAT":
            if msg.autopilot == mavlink2.MAV_AUTOPILOT_INVALID:
                return
            mode = mode_name(msg.custom_mode)
            armed = is_armed(msg.base_mode)
            if vehicle.last_heartbeat_monotonic_s and (mode != vehicle.mode or armed != vehicle.armed):
                self._on_event(f"vehicle {vehicle.system_id}: {'armed' if armed else 'disarmed'}, mode {mode}")
            vehicle.mode, vehicle.armed, vehicle.system_status = mode, armed, msg.system_status
            vehicle.last_heartbeat_monotonic_s = now_s
        elif kind == "LOCAL_POSITION_NED":
            vehicle.altitude_m = -float(msg.z)
        elif kind == "SYS_STATUS":
            vehicle.battery_fraction = msg.battery_remaining / 100.0 if msg.battery_remaining >= 0 else float("nan")
        elif kind == "EXTENDED_SYS_STATE":
            vehicle.landed_state = landed_state_name(msg.landed_state)
        elif kind == "STATUSTEXT":
            text = (msg.text if isinstance(msg.text, str) else bytes(msg.text).decode("utf-8", "replace")).rstrip(chr(0))
            self._on_event(f"vehicle {vehicle.system_id} says: {text}")
            if text.lower().startswith("failsafe"):
                self.failsafes.append(f"vehicle {vehicle.system_id}: {text}")

    async def _flush_loop(self) -> None:
        while True:
            await asyncio.sleep(_TLOG_FLUSH_PERIOD_S)
            for log in self._tlogs.values():
                log.flush()

    async def _heartbeat_loop(self) -> None:
        while True:
            await asyncio.sleep(1.0)
            if self._transport is None:
                continue
            msg = mavlink2.MAVLink_heartbeat_message(
                mavlink2.MAV_TYPE_GCS, mavlink2.MAV_AUTOPILOT_INVALID, 0, 0, mavlink2.MAV_STATE_ACTIVE, 3
            )
            buf = msg.pack(self._mav)
            for addr in list(self._addresses.values()):
                self._transport.sendto(buf, addr)

    def close(self) -> None:
        for task in self._tasks:
            task.cancel()
        if self._transport is not None:
            self._transport.close()
            self._transport = None
        for log in self._tlogs.values():
            log.close()
        self._tlogs.clear()
