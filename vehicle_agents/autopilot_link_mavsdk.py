"""The PX4 SDK path: the one module that imports ``mavsdk``.

MAVSDK (the C++ library behind the ``mavsdk`` 4.x ctypes wrapper) does what a companion computer does with a PX4:
it discovers the autopilot on ``udpin://0.0.0.0:14540+i``, keeps the heartbeat exchange, and re-sends the newest
offboard setpoint at 20 Hz by itself, so the vehicle keeps its offboard proof of life between control steps. If the
agent process dies, that stream dies with it and PX4 falls back after ``COM_OF_LOSS_T``.

Telemetry arrives through MAVSDK subscriptions; each callback only replaces one field of the newest
:class:`AutopilotTelemetry`, and the control loop reads it without waiting.
"""

from __future__ import annotations

import asyncio
import dataclasses
import math
import time
from collections.abc import AsyncIterator, Callable
from typing import Any

from mavsdk.asyncio import Configuration, ComponentType, Mavsdk, MavsdkError
from mavsdk.asyncio.plugins.action import ActionAsync
from mavsdk.asyncio.plugins.offboard import OffboardAsync, VelocityNedYaw
from mavsdk.asyncio.plugins.telemetry import TelemetryAsync
from mavsdk.logging import LogLevel, log_subscribe

from vehicle_agents.autopilot_link import AutopilotLinkError, AutopilotTelemetry

_LOG_LEVEL_TO_KEEP = LogLevel.WARN


def _quiet_mavsdk_log(level: LogLevel, message: str, file: str | None, line: int) -> bool:
    """Keep MAVSDK's warnings and errors on stderr, drop its info chatter (returning True suppresses a line)."""
    return level < _LOG_LEVEL_TO_KEEP


class MavsdkAutopilotLink:
    """An :class:`~vehicle_agents.autopilot_link.AutopilotLink` over MAVSDK."""

    def __init__(self, url: str) -> None:
        self._url = url
        self._telemetry = AutopilotTelemetry()
        self._mavsdk: Mavsdk | None = None
        self._action: ActionAsync | None = None
        self._offboard: OffboardAsync | None = None
        self._telemetry_plugin: TelemetryAsync | None = None
        self._tasks: list[asyncio.Task[None]] = []

    @property
    def telemetry(self) -> AutopilotTelemetry:
        return self._telemetry

    def _update(self, **fields: Any) -> None:
        self._telemetry = dataclasses.replace(self._telemetry, last_message_monotonic_s=time.monotonic(), **fields)

    async def connect(self, timeout_s: float) -> None:
        log_subscribe(_quiet_mavsdk_log)
        self._mavsdk = Mavsdk(Configuration.create_with_component_type(ComponentType.COMPANION_COMPUTER))
        try:
            await self._mavsdk.add_any_connection(self._url)
        except MavsdkError as exc:
            raise AutopilotLinkError(f"cannot open MAVLink connection {self._url}: {exc}") from exc
        system = await self._mavsdk.first_autopilot(timeout_s=timeout_s)
        if system is None:
            raise AutopilotLinkError(f"no autopilot heartbeat on {self._url} within {timeout_s:.0f} s")
        self._action = ActionAsync(system)
        self._offboard = OffboardAsync(system)
        self._telemetry_plugin = TelemetryAsync(system)
        self._start_subscriptions(self._telemetry_plugin)

    def _start_subscriptions(self, tel: TelemetryAsync) -> None:
        def position_velocity(pv: Any) -> None:
            p, v = pv.position, pv.velocity
            self._update(
                position_ned_m=(p.north_m, p.east_m, p.down_m), velocity_ned_mps=(v.north_m_s, v.east_m_s, v.down_m_s)
            )

        def global_position(pos: Any) -> None:
            ok = math.isfinite(pos.latitude_deg) and math.isfinite(pos.longitude_deg)
            self._update(latitude_deg=pos.latitude_deg, longitude_deg=pos.longitude_deg, has_global_position=ok)

        handlers: list[tuple[Callable[[], AsyncIterator[Any]], Callable[[Any], None]]] = [
            (tel.subscribe_position_velocity_ned, position_velocity),
            (tel.subscribe_attitude_euler, lambda e: self._update(yaw_ned_rad=math.radians(e.yaw_deg))),
            (tel.subscribe_armed, lambda a: self._update(armed=bool(a))),
            (tel.subscribe_in_air, lambda a: self._update(in_air=bool(a))),
            (tel.subscribe_flight_mode, lambda m: self._update(flight_mode=m.name)),
            (tel.subscribe_battery, lambda b: self._update(battery_fraction=_battery_fraction(b.remaining_percent))),
            (tel.subscribe_health, lambda h: self._update(ready_to_arm=bool(h.is_armable and h.is_local_position_ok))),
            (tel.subscribe_position, global_position),
        ]
        for subscribe, handle in handlers:
            self._tasks.append(asyncio.create_task(_pump(subscribe, handle)))

    async def arm(self) -> None:
        await self._call("arm", self._require(self._action).arm())

    async def takeoff(self, altitude_m: float) -> None:
        action = self._require(self._action)
        await self._call("set takeoff altitude", action.set_takeoff_altitude(float(altitude_m)))
        await self._call("takeoff", action.takeoff())

    async def start_offboard(self, velocity_ned_mps: tuple[float, float, float], yaw_ned_rad: float) -> None:
        await self.set_velocity_ned(velocity_ned_mps, yaw_ned_rad)
        await self._call("start offboard", self._require(self._offboard).start())

    async def set_velocity_ned(self, velocity_ned_mps: tuple[float, float, float], yaw_ned_rad: float) -> None:
        north, east, down = (float(c) for c in velocity_ned_mps)
        setpoint = VelocityNedYaw(north, east, down, math.degrees(yaw_ned_rad))
        await self._call("set velocity", self._require(self._offboard).set_velocity_ned(setpoint))

    async def hold(self) -> None:
        await self._call("hold", self._require(self._action).hold())

    async def land(self) -> None:
        await self._call("land", self._require(self._action).land())

    async def close(self) -> None:
        for task in self._tasks:
            task.cancel()
        await asyncio.gather(*self._tasks, return_exceptions=True)
        self._tasks.clear()
        if self._mavsdk is not None:
            try:
                self._mavsdk.destroy()
            except Exception:  # noqa: BLE001 - closing must never raise
                pass
            self._mavsdk = None

    @staticmethod
    def _require(plugin: Any) -> Any:
        if plugin is None:
            raise AutopilotLinkError("not connected")
        return plugin

    @staticmethod
    async def _call(what: str, awaitable: Any) -> None:
        try:
            await awaitable
        except MavsdkError as exc:
            raise AutopilotLinkError(f"{what} refused: {exc}") from exc


def _battery_fraction(remaining_percent: float) -> float:
    """MAVSDK reports 0..100; keep 1.0 while the autopilot has not said (NaN)."""
    return remaining_percent / 100.0 if math.isfinite(remaining_percent) else 1.0


async def _pump(subscribe: Callable[[], AsyncIterator[Any]], handle: Callable[[Any], None]) -> None:
    async for value in subscribe():
        handle(value)
