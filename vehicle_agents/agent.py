"""One drone's onboard computer: the asyncio shell around the onboard core, over MAVSDK (or pymavlink) and Zenoh.

Every control period (20 Hz of mission time by default) it gathers the newest telemetry, the perception result of
the newest camera frame, the radio inbox and the ground station's order, calls the pure onboard core with N = 1
(:func:`vehicle_agents.core.onboard.onboard_step`, the same call the lockstep engine makes for the whole fleet), and
does what the core decided: arm, take off, start OFFBOARD, hover or stream the control law's velocity setpoint, and
broadcast the state message. It exits on a stop, after landing, or when its autopilot falls silent (exit code 3).

Its time comes from one of two clocks. Free (a real drone, or ``--clock free``): it keeps its own mission clock and
runs the loop on the wall clock. Paced (a simulation with ``--clock paced``): it computes one tick for each clock
tick the simulator publishes, at that tick's mission time, and acknowledges it once the setpoint and the state
message are out (:class:`~vehicle_agents.sim_clock_link.SimClockLink`); the simulator waits for that before it moves
its vehicles on. Both clocks acknowledge each tick when a clock link is given, so the simulator can measure the
agent's achieved rate.
"""

from __future__ import annotations

import asyncio
import logging
import math
import time
from dataclasses import dataclass, field

import cv2
import numpy as np

from comms.messages import CameraFrame, MissionCommand
from vehicle_agents.autopilot_link import AutopilotLink, AutopilotLinkError, AutopilotTelemetry
from vehicle_agents.control.params import ControlParams
from vehicle_agents.core.onboard import (
    GroundOrder,
    OnboardInputs,
    OnboardOutputs,
    OnboardPlan,
    initial_state,
    onboard_step,
)
from vehicle_agents.core.telemetry import telemetry_batch
from vehicle_agents.flight_phase import Action, Command, Phase, PhaseLimits
from vehicle_agents.mission_clock import MissionClock
from vehicle_agents.perception.result import PerceptionResult
from vehicle_agents.perception.segmentation import perceive
from vehicle_agents.sim_clock_link import SimClockLink
from vehicle_agents.swarm_port import SwarmPort

log = logging.getLogger("vehicle_agents")


def perception_height_m(telemetry: AutopilotTelemetry, frame: CameraFrame) -> float:
    """How far below the camera the ground is, which sets perception's metres per pixel: the autopilot's downward
    rangefinder (DISTANCE_SENSOR; over relief it differs from the altitude above home), else the altitude the camera
    frame carries (a vehicle without a rangefinder, or before its first reading)."""
    reading = telemetry.height_above_ground_m
    return reading if math.isfinite(reading) and reading > 0.0 else frame.altitude_m

EXIT_OK = 0
EXIT_LINK_LOST = 3
EXIT_START_FAILED = 4
_RETRY_COOLDOWN_S = 1.0
_CLOCK_POLL_S = 1.0
"""Paced clock: how often [wall s] a wait for the next clock tick looks at the stop flag. Each look is a wake-up of
the agent's main thread while the clock stands still, so on a starved host (hundreds of agents waiting) it is one
of the few things an idle agent does; a stop is then noticed within a second, well inside the supervisor's grace."""
_COMMANDS = {"start": Command.START, "resume": Command.START, "hold": Command.HOLD, "land": Command.LAND,
             "abort": Command.LAND}


@dataclass(frozen=True)
class AgentConfig:
    """One agent's plan: who it is, where its pad is, and how fast it runs (``speed`` = mission s per wall s)."""

    vehicle_id: int
    role: str
    group: str | None
    pad_enu_m: tuple[float, float]
    has_gps: bool
    params: ControlParams
    control_rate_hz: float = 20.0
    speed: float = 1.0
    paced: bool = False
    """Tick on the simulator's clock ticks (``--clock paced``) instead of the agent's own wall-clock loop."""
    connect_timeout_s: float = 30.0
    limits: PhaseLimits = field(default_factory=PhaseLimits)
    start_delay_s: float = 0.0
    """The mission starts this long after the flood clock [s] (the plan's seeded start jitter); the drone hovers."""


@dataclass
class AgentStats:
    """Counters for the benchmark and the exit log line."""

    control_steps: int = 0
    overruns: int = 0
    frames_processed: int = 0
    frames_dropped: int = 0
    perception_cpu_s: list[float] = field(default_factory=list)
    """Thread CPU time of each frame's perception [s]: the onboard vision's cost, as a companion computer pays it."""
    step_wall_s: list[float] = field(default_factory=list)
    mission_start_t_s: float | None = None
    mission_end_t_s: float | None = None

    def control_rate_hz(self) -> float:
        """Achieved control steps per mission second over the MISSION phase."""
        if self.mission_start_t_s is None or self.mission_end_t_s is None:
            return float("nan")
        span_s = self.mission_end_t_s - self.mission_start_t_s
        return self.control_steps / span_s if span_s > 0 else float("nan")

    def perception_cpu_ms(self) -> tuple[float, float]:
        """(p50, p95) of the perception's CPU time per frame [ms]; NaN before the first frame."""
        if not self.perception_cpu_s:
            return float("nan"), float("nan")
        p50, p95 = np.percentile(self.perception_cpu_s, (50.0, 95.0))
        return 1e3 * float(p50), 1e3 * float(p95)


def decode_image(frame: CameraFrame) -> np.ndarray | None:
    """The frame's BGR image (raw, PNG or JPEG), or None when it does not decode."""
    if frame.encoding == "raw_bgr":
        return np.frombuffer(frame.image, dtype=np.uint8).reshape(frame.height_px, frame.width_px, 3)
    image = cv2.imdecode(np.frombuffer(frame.image, dtype=np.uint8), cv2.IMREAD_COLOR)
    return image if image is not None and image.shape[:2] == (frame.height_px, frame.width_px) else None


class Agent:
    """The onboard loop; :meth:`run` returns the process exit code."""

    def __init__(self, config: AgentConfig, link: AutopilotLink, swarm: SwarmPort,
                 sim_clock: SimClockLink | None = None) -> None:
        if config.paced and sim_clock is None:
            raise ValueError("a paced agent needs the simulator's clock link")
        self.config = config
        self.link = link
        self.swarm = swarm
        self.sim_clock = sim_clock
        self.clock = MissionClock(config.speed)
        self.stats = AgentStats()
        self.plan = OnboardPlan(vehicle_ids=(config.vehicle_id,), roles=(config.role,), pads_en_m=(config.pad_enu_m,),
                                has_gps=(config.has_gps,), params=config.params, limits=config.limits)
        self.state = initial_state(self.plan)
        self._perception: PerceptionResult | None = None
        self._frame_seq = -1
        self._flood_clock_start_s: float | None = None
        self._command_seq = -1
        self._command: Command | None = None
        self._command_wall_s: float | None = None
        self._retry_after_s: dict[Action, float] = {}
        self._last_setpoint: tuple[tuple[float, float, float], float] | None = None
        self._stop_requested = False
        self._t_s = 0.0

    @property
    def phase(self) -> Phase:
        """The flight phase the core is in."""
        return self.state.phases[0]

    def request_stop(self) -> None:
        """SIGTERM/SIGINT: leave the loop at the next period and close everything."""
        self._stop_requested = True

    async def run(self) -> int:
        try:
            return await self._run()
        finally:
            await self.link.close()
            self.swarm.close()

    async def _run(self) -> int:
        """Connect, then one control tick per clock tick until the core says exit; returns the exit code."""
        if not await self._connect():
            return EXIT_START_FAILED
        period_wall_s = self.clock.wall_period_s(1.0 / self.config.control_rate_hz)
        next_tick_s = time.monotonic()
        while True:
            self._t_s = await self._next_paced_tick() if self.config.paced else self.clock.now_s()
            started = time.monotonic()
            outputs = self._compute_tick(started)
            if outputs.actions[0] is Action.EXIT:
                exit_code = self._leave(outputs)
                break
            await self._act(outputs, started)
            if not self.config.paced:
                next_tick_s = await self._sleep_until(next_tick_s + period_wall_s)
        self._finish()
        return exit_code

    async def _connect(self) -> bool:
        """Wait for the autopilot (``connect_timeout_s``); False when it never answered."""
        cfg = self.config
        try:
            await self.link.connect(cfg.connect_timeout_s)
        except AutopilotLinkError as exc:
            log.error("vehicle %d: %s", cfg.vehicle_id, exc)
            return False
        log.info("vehicle %d (%s): autopilot connected", cfg.vehicle_id, cfg.role)
        return True

    def _compute_tick(self, now_wall_s: float) -> OnboardOutputs:
        """Gather this tick's inputs, run the onboard core (N = 1) at mission time ``self._t_s`` and log a change
        of flight phase."""
        order = self._read_order(now_wall_s)
        self._update_perception()
        inputs = OnboardInputs(
            t_s=self._t_s,
            telemetry=telemetry_batch([self.link.telemetry], now_wall_s),
            perception=(self._perception,),
            inbox=(self.swarm.take_inbox(),),
            orders=(order,),
            stop=(self._stop_requested,),
            ranging=(self.swarm.latest_ranging(),),
        )
        old_phase = self.phase
        outputs, self.state = onboard_step(self.plan, self.state, inputs)
        if self.phase is not old_phase:
            log.info("vehicle %d: %s -> %s%s", self.config.vehicle_id, old_phase.value, self.phase.value,
                     " (ground station silent)" if self.phase is Phase.HOLDING and order.command is not Command.HOLD
                     else "")
            self._on_transition(old_phase, self.phase)
        return outputs

    def _leave(self, outputs: OnboardOutputs) -> int:
        """The core said exit: say goodbye (the state message with the leaving flag); the exit code."""
        exit_code = EXIT_OK
        if self.phase is Phase.LINK_LOST:
            log.error("vehicle %d: autopilot silent for %.1f s (vehicle lost); leaving the swarm",
                      self.config.vehicle_id, self.config.limits.link_timeout_s)
            exit_code = EXIT_LINK_LOST
        message = outputs.state_messages[0]
        if message is not None:
            self.swarm.publish_state(message)
        return exit_code

    async def _act(self, outputs: OnboardOutputs, started_wall_s: float) -> None:
        """Do what the core decided, broadcast the state message, then acknowledge the tick (the simulator's clock
        moves on only after the setpoint and the state are out)."""
        action = outputs.actions[0]
        velocity = outputs.velocity_setpoint_ned_mps[0]
        await self._execute(action, (float(velocity[0]), float(velocity[1]), float(velocity[2])),
                            float(outputs.yaw_ned_rad[0]))
        message = outputs.state_messages[0]
        if message is not None:
            self.swarm.publish_state(message)
        if self.sim_clock is not None:
            self.sim_clock.acknowledge(self._t_s)
        if action is Action.FLY:
            self.stats.control_steps += 1
        if self.phase is Phase.MISSION:
            self.stats.step_wall_s.append(time.monotonic() - started_wall_s)

    async def _sleep_until(self, next_tick_s: float) -> float:
        """Free clock: sleep until ``next_tick_s`` [monotonic s], when the next period starts; after an overrun it
        starts now instead. Returns the start of that period, which the one after counts from."""
        delay_s = next_tick_s - time.monotonic()
        if delay_s < 0:
            self.stats.overruns += 1
            next_tick_s = time.monotonic()
            delay_s = 0.0
        await asyncio.sleep(delay_s)
        return next_tick_s

    def _finish(self) -> None:
        """Close the mission's statistics and tell the simulator's clock this agent is leaving."""
        if self.stats.mission_start_t_s is not None and self.stats.mission_end_t_s is None:
            self.stats.mission_end_t_s = self._t_s
        if self.sim_clock is not None:
            self.sim_clock.acknowledge(self._t_s, leaving=True)

    async def _next_paced_tick(self) -> float:
        """Mission time of the next clock tick to compute (each tick is computed at its own time).

        A stop request does not wait for the simulator: it gets a tick one period on, so the core can say goodbye
        (the state message with the leaving flag) even when the clock has stopped.
        """
        assert self.sim_clock is not None
        while True:
            tick = await self.sim_clock.tick_after(self._t_s, _CLOCK_POLL_S)
            if tick is not None:
                return tick.t_s
            if self._stop_requested:
                return self._t_s + 1.0 / self.config.control_rate_hz

    def _on_transition(self, old: Phase, new: Phase) -> None:
        if new is Phase.MISSION:
            self.stats.mission_start_t_s = self._t_s
        if old is Phase.MISSION:
            self.stats.mission_end_t_s = self._t_s

    def _read_order(self, now_wall_s: float) -> GroundOrder:
        """The ground station's newest order addressed to this vehicle, aged on the wall clock."""
        msg: MissionCommand | None = self.swarm.latest_command()
        if msg is not None and msg.seq != self._command_seq:
            self._command_seq = msg.seq
            self._command_wall_s = now_wall_s
            self.clock.observe(msg.t_s)
            if not msg.target_ids or self.config.vehicle_id in msg.target_ids:
                if msg.flood_clock_start_t_s is not None:
                    self._flood_clock_start_s = msg.flood_clock_start_t_s
                if msg.command in _COMMANDS:
                    self._command = _COMMANDS[msg.command]
        age_s = None if self._command_wall_s is None else now_wall_s - self._command_wall_s
        command = self._command
        if command is Command.START and self._flood_clock_start_s is not None and \
                self._t_s < self._flood_clock_start_s + self.config.start_delay_s:
            command = None
        return GroundOrder(command, age_s, self._flood_clock_start_s)

    async def _execute(self, action: Action, velocity_ned_mps: tuple[float, float, float], yaw_ned_rad: float) -> None:
        now_s = time.monotonic()
        if action in (Action.ARM, Action.TAKEOFF, Action.START_OFFBOARD, Action.HOLD, Action.LAND):
            if now_s < self._retry_after_s.get(action, 0.0):
                return
            self._retry_after_s[action] = now_s + _RETRY_COOLDOWN_S
        try:
            if action is Action.ARM:
                await self.link.arm()
            elif action is Action.TAKEOFF:
                await self.link.takeoff(self.config.limits.takeoff_altitude_m)
            elif action is Action.START_OFFBOARD:
                await self.link.start_offboard((0.0, 0.0, 0.0), 0.0)
            elif action in (Action.HOVER, Action.FLY):
                await self._send_setpoint(velocity_ned_mps, yaw_ned_rad)
            elif action is Action.HOLD:
                await self.link.hold()
            elif action is Action.LAND:
                await self.link.land()
        except AutopilotLinkError as exc:
            log.warning("vehicle %d: %s (will retry)", self.config.vehicle_id, exc)

    async def _send_setpoint(self, velocity_ned_mps: tuple[float, float, float], yaw_ned_rad: float) -> None:
        """MAVSDK re-sends the last setpoint by itself, so only changes cross the thread boundary."""
        setpoint = (velocity_ned_mps, yaw_ned_rad)
        if setpoint != self._last_setpoint:
            await self.link.set_velocity_ned(velocity_ned_mps, yaw_ned_rad)
            self._last_setpoint = setpoint

    def _update_perception(self) -> None:
        """Perception, the pure stage before the core, on the newest camera frame (none when nothing new came)."""
        frame = self.swarm.latest_frame()
        if frame is None or frame.seq == self._frame_seq:
            return
        if self._frame_seq >= 0 and frame.seq > self._frame_seq + 1:
            self.stats.frames_dropped += frame.seq - self._frame_seq - 1
        self._frame_seq = frame.seq
        self.clock.observe(frame.t_s)
        image = decode_image(frame)
        if image is None:
            self._perception = PerceptionResult.no_measurement()
            return
        # Edge points go to the ground with the attitude the autopilot reports (ATTITUDE), not the simulator's: a
        # camera without a gimbal knows only its vehicle's estimate. Metres per pixel come from the downward
        # rangefinder's reading (DISTANCE_SENSOR), which over relief is not the altitude above home.
        attitude = self.link.telemetry
        start_cpu_s = time.thread_time()
        self._perception = perceive(image, perception_height_m(attitude, frame), frame.fov_deg, attitude.yaw_ned_rad,
                                    roll_rad=attitude.roll_rad, pitch_rad=attitude.pitch_rad)
        self.stats.perception_cpu_s.append(time.thread_time() - start_cpu_s)
        self.stats.frames_processed += 1
