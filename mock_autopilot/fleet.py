"""A fleet of simulated PX4 vehicles in one process, driven by one asyncio loop on a background thread.

Usage from Python (tests, the mission's simulator bridge)::

    with Fleet([VehicleConfig(0), VehicleConfig(1, has_gps=False, pad_enu_m=(1.5, 0, 0))], base_port=20000) as fleet:
        truth = fleet.truth()          # mission-ENU positions / velocities / yaw of every vehicle
        fleet.kill(1)                  # fault injection
        fleet.drop_counters()          # per vehicle, per link, per reason

The loop ticks every vehicle (physics, timers, due telemetry) at the period the fastest stream needs in wall time
(1 / (rate x speed), between 5 and 20 ms) unless ``tick_period_s`` is given. With ``initial_gate_s`` the clock is
paced (:mod:`mock_autopilot.clock`): :meth:`Fleet.set_gate` lets it run on, the loop ticks at once when the gate
moves, ``last_tick_t_s`` tells when physics and telemetry have reached the gate, and heartbeats keep going on the
wall clock while simulated time stands still (a slow paced run must not look like a lost link).

Instance i (0-based) is MAVLink system i+1; its onboard/API link sends to 127.0.0.1:base_port+i (skipping the GCS
port; another host per vehicle with ``LinkHosts``, see ``ports.py``) and its GCS link to 127.0.0.1:gcs_port (PX4
SITL conventions). Each link binds its own local port (ephemeral by default, PX4's 14580+i / 18570+i with
``px4_local_ports=True``).
"""

from __future__ import annotations

import asyncio
import logging
import math
import threading
import time
from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from comms.frames import local_ned_to_mission_enu, ned_to_enu
from mock_autopilot.clock import SimClock
from mock_autopilot.faults import FAULT_EFFECTS, FaultSpec
from mock_autopilot.mavlink_codec import LinkCodec, SigningState
from mock_autopilot.ports import LinkHosts, onboard_port
from mock_autopilot.px4_streams import GCS, LINKS, ONBOARD, STREAM_PROFILES
from mock_autopilot.telemetry import heartbeat
from mock_autopilot.udp_link import UdpLink
from mock_autopilot.vehicle import Outgoing, Vehicle, VehicleConfig

log = logging.getLogger(__name__)

PX4_ONBOARD_LOCAL_BASE_PORT = 14580
PX4_GCS_LOCAL_BASE_PORT = 18570
MIN_TICK_PERIOD_S = 0.005
MAX_TICK_PERIOD_S = 0.02
WALL_HEARTBEAT_PERIOD_S = 1.0
"""A paced fleet's vehicles send a HEARTBEAT at least this often on the wall clock (PX4's 1 Hz)."""


@dataclass(frozen=True)
class FleetTruth:
    """Ground truth of every vehicle at simulated time ``t_s`` (rows follow the fleet's instance order).

    position_enu_m [m; mission ENU, (N,3)], velocity_enu_mps [m/s; ENU, (N,3)], yaw_ned_rad [rad; PX4 yaw,
    clockwise from north, (N,)], plus armed / alive / has_gps / gps_ok flags and the PX4 mode name.
    """

    t_s: float
    system_ids: NDArray[np.int64]
    position_enu_m: NDArray[np.float64]
    velocity_enu_mps: NDArray[np.float64]
    yaw_ned_rad: NDArray[np.float64]
    armed: NDArray[np.bool_]
    alive: NDArray[np.bool_]
    has_gps: NDArray[np.bool_]
    gps_ok: NDArray[np.bool_]
    modes: tuple[str, ...]


@dataclass(frozen=True)
class VehiclePorts:
    """Where one vehicle's links send to and are bound at (host, port)."""

    onboard_remote: tuple[str, int]
    gcs_remote: tuple[str, int]
    onboard_local: tuple[str, int]
    gcs_local: tuple[str, int]


class Fleet:
    """N vehicles sharing one simulation clock; start/stop from Python (context manager) or the CLI."""

    def __init__(
        self,
        vehicles: Sequence[VehicleConfig] | int,
        base_port: int = 14540,
        gcs_port: int = 14550,
        speed: float = 1.0,
        *,
        host: str | LinkHosts = "127.0.0.1",
        px4_local_ports: bool = False,
        signing_key: bytes | None = None,
        tick_period_s: float | None = None,
        faults: Sequence[FaultSpec] = (),
        initial_gate_s: float = math.inf,
    ) -> None:
        configs = [VehicleConfig(i) for i in range(vehicles)] if isinstance(vehicles, int) else list(vehicles)
        if not configs:
            raise ValueError("a fleet needs at least one vehicle")
        ids = [c.sysid for c in configs]
        if len(set(ids)) != len(ids):
            raise ValueError(f"duplicate system ids in fleet: {ids}")
        if signing_key is not None:
            # MAV_SIGN_CFG 1 (PX4: sign every link but USB) is the default once a key is given; the onboard link
            # to the companion computer plays USB's part and stays unsigned (MAVSDK does not sign).
            configs = [replace(c, params={"MAV_SIGN_CFG": 1, **dict(c.params)}) for c in configs]
        self.configs = configs
        self.base_port = base_port
        self.gcs_port = gcs_port
        self.hosts = host if isinstance(host, LinkHosts) else LinkHosts(host)
        self.host = self.hosts.host
        self.px4_local_ports = px4_local_ports
        self.signing_key = signing_key
        if tick_period_s is None:
            fastest_hz = max(hz for c in configs for link in STREAM_PROFILES[c.stream_profile].values() for hz in link.values())
            tick_period_s = min(MAX_TICK_PERIOD_S, max(MIN_TICK_PERIOD_S, 1.0 / (fastest_hz * speed)))
        self.tick_period_s = tick_period_s
        self._initial_gate_s = initial_gate_s
        self.paced = math.isfinite(initial_gate_s)
        self.clock = SimClock(speed, gate_s=initial_gate_s)
        self._speed = speed
        self._faults = sorted(faults, key=lambda f: f.at_s)
        for f in self._faults:
            if f.instance >= len(configs):
                raise ValueError(f"fault {f.kind} names vehicle {f.instance}, the fleet has {len(configs)}")
        self.vehicles: list[Vehicle] = []
        self.links: list[dict[str, UdpLink]] = []
        self._loop: asyncio.AbstractEventLoop | None = None
        self._thread: threading.Thread | None = None
        self._stop: asyncio.Event | None = None
        self._started = threading.Event()
        self._start_error: BaseException | None = None
        self.tick_overruns = 0
        self.ticks = 0
        self.last_tick_t_s = -math.inf
        """Simulated time of the newest completed tick: physics and due telemetry are out up to here."""
        self._wake: asyncio.Event | None = None
        self._heartbeat_wall_s: list[float] = []

    # ------------------------------------------------------------------ lifecycle
    def __enter__(self) -> Fleet:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def start(self) -> Fleet:
        """Bind every link and start the loop thread; raises OSError if a port is taken."""
        if self._thread is not None:
            raise RuntimeError("fleet already started")
        self._started.clear()
        self._start_error = None
        self._thread = threading.Thread(target=self._thread_main, name="mock-autopilot-fleet", daemon=True)
        self._thread.start()
        self._started.wait()
        if self._start_error is not None:
            self._thread.join()
            self._thread = None
            raise self._start_error
        return self

    def stop(self) -> None:
        """Stop the loop, close every socket, log the drop counters."""
        if self._thread is None:
            return
        if self._loop is not None and self._stop is not None:
            self._loop.call_soon_threadsafe(self._stop.set)
        self._thread.join(timeout=10.0)
        self._thread = None
        for i, counters in self.drop_counters().items():
            log.info("system %d drops: %s", i, counters)
        skipped = sum(link.repeated_setpoints.skipped for links in self.links for link in links.values()
                      if link.repeated_setpoints is not None)
        if self.paced:
            log.info("re-sent setpoints skipped while the paced clock stood still: %d", skipped)

    def _thread_main(self) -> None:
        loop = asyncio.new_event_loop()
        self._loop = loop
        try:
            loop.run_until_complete(self._main())
        except BaseException as exc:  # reported to start() or logged; the thread must not die silently
            if not self._started.is_set():
                self._start_error = exc
            else:
                log.exception("fleet loop crashed")
        finally:
            self._started.set()
            loop.close()

    async def _main(self) -> None:
        self._stop = asyncio.Event()
        self._wake = asyncio.Event()
        self.clock = SimClock(self._speed, gate_s=self._initial_gate_s)
        self.vehicles, self.links = [], []
        now = self.clock.now_s()
        try:
            for i, config in enumerate(self.configs):
                vehicle = Vehicle(config, now)
                vehicle.stream_slack_s = 0.5 * self.tick_period_s * self._speed
                self.vehicles.append(vehicle)
                self.links.append(await self._open_links(i, vehicle))
        except BaseException:
            self._close_links()
            raise
        self._started.set()
        try:
            await self._run_ticks()
        finally:
            self._close_links()

    async def _open_links(self, i: int, vehicle: Vehicle) -> dict[str, UdpLink]:
        links: dict[str, UdpLink] = {}
        onboard = (self.hosts.onboard_host(vehicle.system_id), onboard_port(self.base_port, i, self.gcs_port))
        remotes = {ONBOARD: onboard, GCS: (self.host, self.gcs_port)}
        local_ports = {
            ONBOARD: PX4_ONBOARD_LOCAL_BASE_PORT + i if self.px4_local_ports else 0,
            GCS: PX4_GCS_LOCAL_BASE_PORT + i if self.px4_local_ports else 0,
        }
        sign_cfg = vehicle.params.get_int("MAV_SIGN_CFG")
        for name in LINKS:
            signing = None
            if self.signing_key is not None and (sign_cfg == 2 or (sign_cfg == 1 and name == GCS)):
                signing = SigningState(self.signing_key, required=True, link_id=LINKS.index(name))
            codec = LinkCodec(vehicle.system_id, 1, signing)
            link = UdpLink(name, codec, remotes[name], self.clock, self._make_sink(i),
                           skip_repeated_setpoints=self.paced and name == ONBOARD)
            links[name] = link
            await link.open((self.hosts.bind_host, local_ports[name]))
        return links

    def _close_links(self) -> None:
        for links in self.links:
            for link in links.values():
                link.close()

    def _make_sink(self, i: int):  # type: ignore[no-untyped-def]
        def on_message(link_name: str, message) -> None:  # type: ignore[no-untyped-def]
            self._dispatch(i, self.vehicles[i].handle(link_name, message, self.clock.now_s()))

        return on_message

    def _dispatch(self, i: int, outgoing: list[Outgoing]) -> None:
        if not outgoing:
            return
        links = self.links[i]
        for item in outgoing:
            if self.paced and item.message.get_type() == "HEARTBEAT":
                self._heartbeat_wall_s[i] = time.monotonic()
            if item.link is None:
                for link in links.values():
                    link.send(item.message)
            else:
                links[item.link].send(item.message)
        for link in links.values():
            link.flush()

    async def _run_ticks(self) -> None:
        assert self._stop is not None and self._wake is not None
        next_wall = time.monotonic()
        self._heartbeat_wall_s = [next_wall] * len(self.vehicles)
        while not self._stop.is_set():
            now = self.clock.now_s()
            self._apply_due_faults(now)
            if now > self.last_tick_t_s or not self.paced:  # a paced clock standing still changes nothing
                for i, vehicle in enumerate(self.vehicles):
                    self._dispatch(i, vehicle.tick(now))
            if self.paced:
                self._wall_heartbeats()
            self.ticks += 1
            self.last_tick_t_s = now
            next_wall += self.tick_period_s
            delay = next_wall - time.monotonic()
            if delay < 0:
                self.tick_overruns += 1
                next_wall = time.monotonic()
                delay = 0.0
            if not self.paced:
                await asyncio.sleep(delay)  # stop is noticed within one tick; cheaper than wait_for on the event
                continue
            self._wake.clear()
            try:
                await asyncio.wait_for(self._wake.wait(), delay)
                next_wall = time.monotonic()
            except asyncio.TimeoutError:
                pass

    def _wall_heartbeats(self) -> None:
        """While a paced clock stands still, simulated-time streams stop; the heartbeat goes on at 1 Hz of wall time."""
        wall_s = time.monotonic()
        for i, vehicle in enumerate(self.vehicles):
            if vehicle.killed or wall_s - self._heartbeat_wall_s[i] < WALL_HEARTBEAT_PERIOD_S:
                continue
            self._heartbeat_wall_s[i] = wall_s
            message = heartbeat(vehicle.snapshot(self.clock.now_s()))
            for link in self.links[i].values():
                link.send(message)
                link.flush()

    def set_gate(self, gate_s: float) -> None:
        """Let a paced clock run up to ``gate_s`` and tick at once (thread-safe)."""
        self.clock.set_gate(gate_s)
        if self._loop is not None and self._wake is not None:
            self._loop.call_soon_threadsafe(self._wake.set)

    def _apply_due_faults(self, now_s: float) -> None:
        while self._faults and self._faults[0].at_s <= now_s:
            fault = self._faults.pop(0)
            log.info("fault %s on instance %d at t=%.1f s", fault.kind, fault.instance, now_s)
            self._apply_fault(fault)

    def _apply_fault(self, fault: FaultSpec) -> None:
        links = list(self.links[fault.instance].values())
        FAULT_EFFECTS[fault.kind](self.vehicles[fault.instance], links, fault, self.clock.now_s())

    def _call_in_loop(self, fault: FaultSpec) -> None:
        if self._loop is None or self._thread is None:
            raise RuntimeError("fleet is not running")
        done = threading.Event()

        def apply() -> None:
            try:
                self._apply_fault(fault)
            finally:
                done.set()

        self._loop.call_soon_threadsafe(apply)
        done.wait(timeout=5.0)

    # ------------------------------------------------------------------ fault API
    def kill(self, instance: int) -> None:
        """Power loss of vehicle ``instance``: it stops talking and falls."""
        self._call_in_loop(FaultSpec("kill", instance, 0.0))

    def lose_gps(self, instance: int) -> None:
        """Vehicle ``instance`` loses its GPS (global position invalid, local stays)."""
        self._call_in_loop(FaultSpec("gps", instance, 0.0))

    def drain_battery(self, instance: int, remaining_fraction: float) -> None:
        """Set vehicle ``instance``'s battery to ``remaining_fraction`` (0..1); battery failsafes follow."""
        self._call_in_loop(FaultSpec("battery", instance, 0.0, remaining_fraction))

    def drop_links(self, instance: int) -> None:
        """Drop every datagram to and from vehicle ``instance`` (both links) until :meth:`restore_links`."""
        self._call_in_loop(FaultSpec("drop", instance, 0.0))

    def delay_links(self, instance: int, delay_s: float) -> None:
        """Delay every datagram to and from vehicle ``instance`` by ``delay_s`` simulated seconds."""
        self._call_in_loop(FaultSpec("delay", instance, 0.0, delay_s))

    def restore_links(self, instance: int) -> None:
        """End drop and delay faults on vehicle ``instance``."""
        self._call_in_loop(FaultSpec("restore", instance, 0.0))

    # ------------------------------------------------------------------ observation
    def truth(self) -> FleetTruth:
        """True state of every vehicle in the mission ENU frame (for cameras, the radio emulator, metrics)."""
        now = self.clock.now_s()
        bodies = [v.body for v in self.vehicles]
        pads = np.array([v.config.pad_enu_m for v in self.vehicles], dtype=float).reshape(-1, 3)
        pos_ned = np.array([b.position_ned_m for b in bodies], dtype=float).reshape(-1, 3)
        vel_ned = np.array([b.velocity_ned_mps for b in bodies], dtype=float).reshape(-1, 3)
        return FleetTruth(
            t_s=now,
            system_ids=np.array([v.system_id for v in self.vehicles], dtype=np.int64),
            position_enu_m=local_ned_to_mission_enu(pos_ned, pads),
            velocity_enu_mps=ned_to_enu(vel_ned),
            yaw_ned_rad=np.array([v.yaw_rad for v in self.vehicles], dtype=float),
            armed=np.array([v.armed for v in self.vehicles], dtype=bool),
            alive=np.array([not v.killed for v in self.vehicles], dtype=bool),
            has_gps=np.array([v.config.has_gps for v in self.vehicles], dtype=bool),
            gps_ok=np.array([v.global_position_valid for v in self.vehicles], dtype=bool),
            modes=tuple(v.mode.value for v in self.vehicles),
        )

    def ports(self, instance: int) -> VehiclePorts:
        """Remote and bound addresses of vehicle ``instance``'s links."""
        links, vid = self.links[instance], self.vehicles[instance].system_id
        return VehiclePorts((self.hosts.onboard_host(vid), onboard_port(self.base_port, instance, self.gcs_port)),
                            (self.host, self.gcs_port), links[ONBOARD].local_address, links[GCS].local_address)

    def drop_counters(self) -> dict[int, dict[str, dict[str, int]]]:
        """system id -> link -> reason -> count, for every datagram or frame the vehicle refused.

        Link-level reasons come from the codec (garbage, bad_crc, unknown_msgid, wrong_target_system, unsigned,
        ...) and fault injection (``fault_inbound``); ``vehicle`` holds semantic refusals (bad setpoints,
        rejected parameters, refused commands).
        """
        result: dict[int, dict[str, dict[str, int]]] = {}
        for vehicle, links in zip(self.vehicles, self.links):
            entry: dict[str, dict[str, int]] = {}
            for name, link in links.items():
                counts = dict(link.codec.drops)
                for k, n in link.fault_drops.items():
                    counts[f"fault_{k}"] = n
                entry[name] = counts
            entry["vehicle"] = dict(vehicle.rejections)
            result[vehicle.system_id] = entry
        return result
