"""The plain-MAVLink alternative to MAVSDK (``--link pymavlink``): the same PX4 offboard recipe by hand.

Useful where the MAVSDK library is not available, and as a second, independent client of the autopilot. A reader
thread keeps the newest telemetry and matches COMMAND_ACKs; a streamer thread re-sends the newest velocity setpoint
at 20 Hz (what MAVSDK does, and what PX4's offboard proof of life needs); commands are COMMAND_LONGs retried until
acknowledged, as MAVSDK and QGroundControl do.
"""

from __future__ import annotations

import asyncio
import dataclasses
import math
import os
import threading
import time
from typing import Any

from comms.px4 import MODE_TABLE, LandedState, MavResult, Px4Mode, is_armed, mavsdk_mode_name
from vehicle_agents.autopilot_link import AutopilotLinkError, AutopilotTelemetry

os.environ.setdefault("MAVLINK20", "1")
from pymavlink import mavutil  # noqa: E402

_ml = mavutil.mavlink
_AIRBORNE = frozenset(int(state) for state in LandedState if state.airborne)
_SETPOINT_PERIOD_S = 0.05
_VELOCITY_YAW_TYPE_MASK = 0b0000_1001_1100_0111  # 2503: use vx, vy, vz and yaw (as MAVSDK's set_velocity_ned)
_ACK_TIMEOUT_S = 1.0
_ACK_RETRIES = 3
_PREARM_CHECK_BIT = _ml.MAV_SYS_STATUS_PREARM_CHECK
_OFFBOARD = MODE_TABLE[Px4Mode.OFFBOARD]
_HOLD = MODE_TABLE[Px4Mode.AUTO_LOITER]


def _pymavlink_url(url: str) -> str:
    """``udpin://0.0.0.0:14540`` (MAVSDK style) -> ``udpin:0.0.0.0:14540`` (pymavlink style)."""
    scheme, sep, rest = url.partition("://")
    return f"{scheme}:{rest}" if sep else url


class PymavlinkAutopilotLink:
    """An :class:`~vehicle_agents.autopilot_link.AutopilotLink` over pymavlink."""

    def __init__(self, url: str) -> None:
        self._url = _pymavlink_url(url)
        self._telemetry = AutopilotTelemetry()
        self._conn: Any = None
        self._target_system = 0
        self._lock = threading.Lock()
        self._acks: dict[int, int] = {}
        self._setpoint: tuple[tuple[float, float, float], float] | None = None
        self._stop = threading.Event()
        self._heartbeat_sent_s = 0.0
        self._threads: list[threading.Thread] = []

    @property
    def telemetry(self) -> AutopilotTelemetry:
        return self._telemetry

    def _update(self, **fields: Any) -> None:
        self._telemetry = dataclasses.replace(self._telemetry, last_message_monotonic_s=time.monotonic(), **fields)

    async def connect(self, timeout_s: float) -> None:
        try:
            self._conn = mavutil.mavlink_connection(self._url, source_system=self._source_system(),
                                                    source_component=_ml.MAV_COMP_ID_ONBOARD_COMPUTER)
        except OSError as exc:
            raise AutopilotLinkError(f"cannot open MAVLink connection {self._url}: {exc}") from exc
        heartbeat = await asyncio.to_thread(self._conn.wait_heartbeat, timeout=timeout_s)
        if heartbeat is None:
            raise AutopilotLinkError(f"no autopilot heartbeat on {self._url} within {timeout_s:.0f} s")
        self._target_system = heartbeat.get_srcSystem()
        for target in (self._read_loop, self._stream_loop):
            thread = threading.Thread(target=target, daemon=True)
            thread.start()
            self._threads.append(thread)

    @staticmethod
    def _source_system() -> int:
        return 245  # a companion computer's own system id would be configured per vehicle; any non-PX4 id works

    def _read_loop(self) -> None:
        while not self._stop.is_set():
            msg = self._conn.recv_match(blocking=True, timeout=0.1)
            if msg is None or msg.get_srcSystem() != self._target_system:
                continue
            kind = msg.get_type()
            if kind == "HEARTBEAT":
                self._update(armed=is_armed(msg.base_mode), flight_mode=mavsdk_mode_name(msg.custom_mode))
            elif kind == "LOCAL_POSITION_NED":
                self._update(position_ned_m=(msg.x, msg.y, msg.z), velocity_ned_mps=(msg.vx, msg.vy, msg.vz))
            elif kind == "ATTITUDE":
                self._update(yaw_ned_rad=float(msg.yaw), roll_rad=float(msg.roll), pitch_rad=float(msg.pitch))
            elif kind == "EXTENDED_SYS_STATE":
                self._update(in_air=msg.landed_state in _AIRBORNE)
            elif kind == "SYS_STATUS":
                ready = bool(msg.onboard_control_sensors_health & _PREARM_CHECK_BIT)
                battery = msg.battery_remaining / 100.0 if msg.battery_remaining >= 0 else 1.0
                self._update(ready_to_arm=ready, battery_fraction=battery)
            elif kind == "GLOBAL_POSITION_INT":
                self._update(latitude_deg=msg.lat / 1e7, longitude_deg=msg.lon / 1e7, has_global_position=True)
            elif kind == "DISTANCE_SENSOR" and msg.orientation == _ml.MAV_SENSOR_ROTATION_PITCH_270:
                if msg.current_distance > 0:
                    self._update(height_above_ground_m=msg.current_distance / 100.0)
            elif kind == "COMMAND_ACK":
                with self._lock:
                    self._acks[msg.command] = msg.result

    def _stream_loop(self) -> None:
        next_s = time.monotonic()
        while not self._stop.is_set():
            setpoint = self._setpoint
            if setpoint is not None:
                (vn, ve, vd), yaw = setpoint
                self._conn.mav.set_position_target_local_ned_send(
                    0, self._target_system, 1, _ml.MAV_FRAME_LOCAL_NED, _VELOCITY_YAW_TYPE_MASK,
                    0.0, 0.0, 0.0, vn, ve, vd, 0.0, 0.0, 0.0, yaw, 0.0)
            if time.monotonic() - self._heartbeat_sent_s >= 1.0:
                self._conn.mav.heartbeat_send(_ml.MAV_TYPE_ONBOARD_CONTROLLER, _ml.MAV_AUTOPILOT_INVALID, 0, 0,
                                              _ml.MAV_STATE_ACTIVE)
                self._heartbeat_sent_s = time.monotonic()
            next_s += _SETPOINT_PERIOD_S
            self._stop.wait(max(0.0, next_s - time.monotonic()))

    def _command_blocking(self, what: str, command: int, *params: float) -> None:
        values = list(params) + [0.0] * (7 - len(params))
        for attempt in range(_ACK_RETRIES):
            with self._lock:
                self._acks.pop(command, None)
            self._conn.mav.command_long_send(self._target_system, 1, command, attempt, *values)
            deadline = time.monotonic() + _ACK_TIMEOUT_S
            while time.monotonic() < deadline:
                with self._lock:
                    result = self._acks.pop(command, None)
                if result is not None:
                    if result in (MavResult.ACCEPTED, MavResult.IN_PROGRESS):
                        return
                    raise AutopilotLinkError(f"{what} refused (MAV_RESULT {result})")
                time.sleep(0.01)
        raise AutopilotLinkError(f"{what}: no COMMAND_ACK after {_ACK_RETRIES} tries")

    async def _command(self, what: str, command: int, *params: float) -> None:
        await asyncio.to_thread(self._command_blocking, what, command, *params)

    async def arm(self) -> None:
        await self._command("arm", _ml.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)

    async def takeoff(self, altitude_m: float) -> None:
        self._conn.mav.param_set_send(self._target_system, 1, b"MIS_TAKEOFF_ALT", float(altitude_m),
                                      _ml.MAV_PARAM_TYPE_REAL32)
        nan = math.nan
        await self._command("takeoff", _ml.MAV_CMD_NAV_TAKEOFF, nan, 0.0, 0.0, nan, nan, nan, nan)

    async def start_offboard(self, velocity_ned_mps: tuple[float, float, float], yaw_ned_rad: float) -> None:
        await self.set_velocity_ned(velocity_ned_mps, yaw_ned_rad)
        await asyncio.sleep(2 * _SETPOINT_PERIOD_S)
        await self._command("start offboard", _ml.MAV_CMD_DO_SET_MODE, _ml.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED,
                            _OFFBOARD.main_mode, _OFFBOARD.sub_mode)

    async def set_velocity_ned(self, velocity_ned_mps: tuple[float, float, float], yaw_ned_rad: float) -> None:
        self._setpoint = (tuple(float(c) for c in velocity_ned_mps), float(yaw_ned_rad))  # type: ignore[assignment]

    async def hold(self) -> None:
        self._setpoint = None
        await self._command("hold", _ml.MAV_CMD_DO_SET_MODE, _ml.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED,
                            _HOLD.main_mode, _HOLD.sub_mode)

    async def land(self) -> None:
        self._setpoint = None
        await self._command("land", _ml.MAV_CMD_NAV_LAND)

    async def close(self) -> None:
        self._stop.set()
        for thread in self._threads:
            await asyncio.to_thread(thread.join, 1.0)
        self._threads.clear()
        if self._conn is not None:
            try:
                self._conn.close()
            except Exception:  # noqa: BLE001 - closing must never raise
                pass
            self._conn = None
