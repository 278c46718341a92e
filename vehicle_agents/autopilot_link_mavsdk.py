"""The PX4 SDK path: the one module that imports ``mavsdk``.

MAVSDK (the C++ library behind the ``mavsdk`` 4.x ctypes wrapper) does what a companion computer does with a PX4:
it discovers the autopilot on ``udpin://0.0.0.0:14540+i``, keeps the heartbeat exchange, and re-sends the newest
offboard setpoint at 20 Hz by itself, so the vehicle keeps its offboard proof of life between control steps. If the
agent process dies, that stream dies with it and PX4 falls back after ``COM_OF_LOSS_T``.

Cost per control tick is what limits how many agents one host runs, so this module uses MAVSDK's plain (callback)
API rather than its ``mavsdk.asyncio`` wrappers:

* telemetry callbacks run on MAVSDK's user-callback thread and only store the value; the asyncio wrappers would
  instead wake the agent's event loop for every MAVLink message (``call_soon_threadsafe`` + a queue + a task step per
  message, ~50 wake-ups per second), although the control loop only reads the newest values once per tick;
* the :class:`AutopilotTelemetry` snapshot is built when the control loop reads it, once per tick, not per message;
* a velocity setpoint is handed to MAVSDK directly (``Offboard::set_velocity_ned`` only stores it and sends one
  SET_POSITION_TARGET_LOCAL_NED), not through a thread-pool hop and back per tick.

Commands that wait for the autopilot's COMMAND_ACK (arm, takeoff, offboard start, hold, land) still run in a worker
thread so the control loop never blocks on them.

Every MAVLink message costs MAVSDK two thread wake-ups (its I/O thread, then its callback thread) whether or not
anyone reads it, so on connecting the link asks the autopilot (MAV_CMD_SET_MESSAGE_INTERVAL, through MAVSDK's
``set_rate_*``) for the streams it reads at the rates it needs and to stop fast streams nobody here reads. PX4's
onboard link streams ATTITUDE at 100 Hz, GLOBAL_POSITION_INT at 50 Hz, LOCAL_POSITION_NED at 30 Hz and ALTITUDE and
VFR_HUD at 10 Hz by default; the mock's reduced profile already sends close to :data:`TELEMETRY_RATES_HZ`.
"""

from __future__ import annotations

import asyncio
import logging
import math
import time
from collections.abc import Callable, Mapping
from typing import Any

from mavsdk import ComponentType, Configuration, Mavsdk, MavsdkError
from mavsdk.logging import LogLevel, log_subscribe
from mavsdk.plugins.action import Action
from mavsdk.plugins.offboard import Offboard, VelocityNedYaw
from mavsdk.plugins.telemetry import Telemetry
from mavsdk.system import System

from vehicle_agents.autopilot_link import AutopilotLinkError, AutopilotTelemetry

log = logging.getLogger("vehicle_agents")
_LOG_LEVEL_TO_KEEP = LogLevel.WARN

TELEMETRY_RATES_HZ: dict[str, float] = {
    "position_velocity_ned": 20.0,  # LOCAL_POSITION_NED: the control law's input, at the default control rate
    "attitude_euler": 10.0,  # ATTITUDE: the heading perception projects the camera's edge points with
    "position": 10.0,  # GLOBAL_POSITION_INT: the GPS leader's latitude/longitude for the ground station
    "distance_sensor": 2.0,  # DISTANCE_SENSOR: the ground's distance, perception's scale (relief changes slowly)
    "altitude": -1.0,  # ALTITUDE: not read
    "fixedwing_metrics": -1.0,  # VFR_HUD: not read
}
"""MAVSDK ``Telemetry.set_rate_<name>`` -> rate [Hz of the autopilot's clock]; -1 stops the stream (MAVSDK sends
interval -1), 0 would restore the autopilot's default."""


def _quiet_mavsdk_log(level: LogLevel, message: str, file: str | None, line: int) -> bool:
    """Keep MAVSDK's warnings and errors on stderr, drop its info chatter (returning True suppresses a line)."""
    return level < _LOG_LEVEL_TO_KEEP


class _TelemetryFields:
    """The newest value of every telemetry field, written by MAVSDK's callback thread, read by the control loop.

    Each callback replaces whole attributes (one assignment each, atomic under the GIL); position and velocity come
    from one LOCAL_POSITION_NED and are stored as one tuple so a reader never pairs two different messages.
    """

    def __init__(self) -> None:
        default = AutopilotTelemetry()
        self.position_velocity_ned: tuple[tuple[float, float, float], tuple[float, float, float]] = (
            default.position_ned_m, default.velocity_ned_mps)
        self.attitude_rad = (default.roll_rad, default.pitch_rad, default.yaw_ned_rad)
        """(roll, pitch, yaw) of one ATTITUDE, stored together so a reader never mixes two messages."""
        self.armed = default.armed
        self.in_air = default.in_air
        self.flight_mode = default.flight_mode
        self.battery_fraction = default.battery_fraction
        self.ready_to_arm = default.ready_to_arm
        self.global_position: tuple[bool, float, float] = (
            default.has_global_position, default.latitude_deg, default.longitude_deg)
        self.height_above_ground_m = default.height_above_ground_m
        self.last_message_monotonic_s = default.last_message_monotonic_s

    def snapshot(self) -> AutopilotTelemetry:
        position, velocity = self.position_velocity_ned
        roll, pitch, yaw = self.attitude_rad
        has_global, latitude, longitude = self.global_position
        return AutopilotTelemetry(
            position_ned_m=position, velocity_ned_mps=velocity, yaw_ned_rad=yaw, roll_rad=roll, pitch_rad=pitch,
            armed=self.armed,
            in_air=self.in_air, flight_mode=self.flight_mode, battery_fraction=self.battery_fraction,
            ready_to_arm=self.ready_to_arm, has_global_position=has_global, latitude_deg=latitude,
            longitude_deg=longitude, height_above_ground_m=self.height_above_ground_m,
            last_message_monotonic_s=self.last_message_monotonic_s)


class MavsdkAutopilotLink:
    """An :class:`~vehicle_agents.autopilot_link.AutopilotLink` over MAVSDK."""

    def __init__(self, url: str, telemetry_rates_hz: Mapping[str, float] | None = TELEMETRY_RATES_HZ) -> None:
        """``telemetry_rates_hz``: the stream rates to request on connecting (e.g. ``position_velocity_ned`` at the
        agent's own control rate); None leaves every stream at the autopilot's rate."""
        self._url = url
        self._rates_hz = dict(telemetry_rates_hz or {})
        self._fields = _TelemetryFields()
        self._mavsdk: Mavsdk | None = None
        self._action: Action | None = None
        self._offboard: Offboard | None = None
        self._telemetry_plugin: Telemetry | None = None

    @property
    def telemetry(self) -> AutopilotTelemetry:
        return self._fields.snapshot()

    async def connect(self, timeout_s: float) -> None:
        log_subscribe(_quiet_mavsdk_log)
        self._mavsdk = Mavsdk(Configuration.create_with_component_type(ComponentType.COMPANION_COMPUTER))
        try:
            await asyncio.to_thread(self._mavsdk.add_any_connection_with_handle, self._url)
        except MavsdkError as exc:
            raise AutopilotLinkError(f"cannot open MAVLink connection {self._url}: {exc}") from exc
        system = await self._first_autopilot(self._mavsdk, timeout_s)
        if system is None:
            raise AutopilotLinkError(f"no autopilot heartbeat on {self._url} within {timeout_s:.0f} s")
        self._action = Action(system)
        self._offboard = Offboard(system)
        self._telemetry_plugin = Telemetry(system)
        self._start_subscriptions(self._telemetry_plugin)
        await self._request_rates(self._telemetry_plugin)

    async def _request_rates(self, tel: Telemetry) -> None:
        """Ask for the stream rates in ``_rates_hz``; an autopilot that refuses one keeps its own rate for it."""
        for name, rate_hz in self._rates_hz.items():
            try:
                await asyncio.to_thread(getattr(tel, f"set_rate_{name}"), rate_hz)
            except MavsdkError as exc:
                log.warning("%s: autopilot kept its rate for %s (%s)", self._url, name, exc)

    @staticmethod
    async def _first_autopilot(mavsdk: Mavsdk, timeout_s: float) -> System | None:
        """Wait for the autopilot's heartbeat without holding a thread, so a stop during start-up ends the wait."""
        loop = asyncio.get_running_loop()
        found: asyncio.Future[System | None] = loop.create_future()

        def on_result(system: System | None) -> None:
            loop.call_soon_threadsafe(lambda: found.done() or found.set_result(system))

        handle = mavsdk.first_autopilot_async(timeout_s, on_result)
        try:
            return await found
        finally:
            mavsdk.cancel_first_autopilot(handle)

    def _start_subscriptions(self, tel: Telemetry) -> None:
        """Subscribe to exactly what the agent reads; every callback stores, stamps and returns."""
        fields = self._fields

        def stamped(store: Callable[[Any], None]) -> Callable[[Any, Any], None]:
            def callback(value: Any, _user_data: Any) -> None:
                store(value)
                fields.last_message_monotonic_s = time.monotonic()
            return callback

        def position_velocity(pv: Any) -> None:
            p, v = pv.position, pv.velocity
            fields.position_velocity_ned = ((p.north_m, p.east_m, p.down_m), (v.north_m_s, v.east_m_s, v.down_m_s))

        def global_position(pos: Any) -> None:
            ok = math.isfinite(pos.latitude_deg) and math.isfinite(pos.longitude_deg)
            fields.global_position = (ok, pos.latitude_deg, pos.longitude_deg)

        def attitude(e: Any) -> None:
            fields.attitude_rad = (math.radians(e.roll_deg), math.radians(e.pitch_deg), math.radians(e.yaw_deg))

        def armed(a: Any) -> None:
            fields.armed = bool(a)

        def in_air(a: Any) -> None:
            fields.in_air = bool(a)

        def flight_mode(m: Any) -> None:
            fields.flight_mode = m.name

        def battery(b: Any) -> None:
            fields.battery_fraction = _battery_fraction(b.remaining_percent)

        def distance_sensor(d: Any) -> None:
            distance = float(d.current_distance_m)
            if math.isfinite(distance) and distance > 0.0:
                fields.height_above_ground_m = distance

        def health(h: Any) -> None:
            fields.ready_to_arm = bool(h.is_armable and h.is_local_position_ok)

        tel.subscribe_position_velocity_ned(stamped(position_velocity))
        tel.subscribe_attitude_euler(stamped(attitude))
        tel.subscribe_armed(stamped(armed))
        tel.subscribe_in_air(stamped(in_air))
        tel.subscribe_flight_mode(stamped(flight_mode))
        tel.subscribe_battery(stamped(battery))
        tel.subscribe_health(stamped(health))
        tel.subscribe_position(stamped(global_position))
        tel.subscribe_distance_sensor(stamped(distance_sensor))

    async def arm(self) -> None:
        await self._call("arm", self._require(self._action).arm)

    async def takeoff(self, altitude_m: float) -> None:
        action = self._require(self._action)
        await self._call("set takeoff altitude", action.set_takeoff_altitude, float(altitude_m))
        await self._call("takeoff", action.takeoff)

    async def start_offboard(self, velocity_ned_mps: tuple[float, float, float], yaw_ned_rad: float) -> None:
        await self.set_velocity_ned(velocity_ned_mps, yaw_ned_rad)
        await self._call("start offboard", self._require(self._offboard).start)

    async def set_velocity_ned(self, velocity_ned_mps: tuple[float, float, float], yaw_ned_rad: float) -> None:
        """Store the setpoint in MAVSDK, which sends it at once and keeps re-sending it (no wait for an answer)."""
        north, east, down = (float(c) for c in velocity_ned_mps)
        setpoint = VelocityNedYaw(north, east, down, math.degrees(yaw_ned_rad))
        try:
            self._require(self._offboard).set_velocity_ned(setpoint)
        except MavsdkError as exc:
            raise AutopilotLinkError(f"set velocity refused: {exc}") from exc

    async def hold(self) -> None:
        await self._call("hold", self._require(self._action).hold)

    async def land(self) -> None:
        await self._call("land", self._require(self._action).land)

    async def close(self) -> None:
        """Release the plugins (their subscriptions end, no callback runs after this) before MAVSDK itself."""
        owned: list[Any] = [self._telemetry_plugin, self._offboard, self._action, self._mavsdk]
        self._telemetry_plugin = self._offboard = self._action = self._mavsdk = None
        for thing in owned:
            if thing is None:
                continue
            try:
                thing.destroy()
            except Exception:  # noqa: BLE001 - closing must never raise
                pass

    @staticmethod
    def _require(plugin: Any) -> Any:
        if plugin is None:
            raise AutopilotLinkError("not connected")
        return plugin

    @staticmethod
    async def _call(what: str, blocking: Callable[..., Any], *args: Any) -> None:
        """Run a command that waits for the autopilot's answer in a worker thread."""
        try:
            await asyncio.to_thread(blocking, *args)
        except MavsdkError as exc:
            raise AutopilotLinkError(f"{what} refused: {exc}") from exc


def _battery_fraction(remaining_percent: float) -> float:
    """MAVSDK reports 0..100; keep 1.0 while the autopilot has not said (NaN)."""
    return remaining_percent / 100.0 if math.isfinite(remaining_percent) else 1.0
