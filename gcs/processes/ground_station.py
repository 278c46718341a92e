"""The process engine's ground station: starts the mission's processes, watches them, records, reports.

Sequence (SPEC §1, §6), the phases being :mod:`gcs.processes.mission_phase`'s pure machine:

1. open the mission's Zenoh hub (the port outside clients join) and the MAVLink GCS port, so a busy port fails
   before any child starts; start the simulation's processes (:mod:`gcs.processes.mission_children`);
2. STARTING: wait until every vehicle is heard on the GCS link and every agent holds its liveliness token;
3. TAKEOFF: the agents arm, take off and switch to OFFBOARD on their own; when the GCS link shows every vehicle
   armed, airborne and in OFFBOARD, the ground station starts the flood clock and commands ``start``;
4. MISSION: aggregates and publishes the caged polygon, reports vehicles and agents lost;
5. at the end of the flood clock it commands ``hold``, stops every process and writes the outputs, with two
   verdicts (:mod:`gcs.processes.run_verdict`): engine health and safety.

What only a simulation has (ground truth, the live IoU and coverage, the simulator's pace) lives in
:mod:`gcs.processes.sim_evaluation` and :mod:`gcs.processes.pace_watch`; with ``simulated=False`` the station starts
no process and flies with the vehicles and agents it finds (real drones), on the agents' mission clock.
Watchdogs stay on the wall clock (the vehicles' heartbeats go on while a paced simulated time stands still), so a
slow paced run is never a lost link. Any failure (a child that dies early, a timeout, Ctrl-C) ends the run with one
clear message and a non-zero exit code; every path stops every child and writes what was recorded.
"""

from __future__ import annotations

import asyncio
import datetime as dt
import signal
import time
import traceback
from pathlib import Path

from rich.console import Console

from comms.key_file import KeyFileError, read_key_file
from comms.keys import MissionKeys
from comms.messages import MissionCommand, NeighbourState, encode
from comms.signing import MissionKey
from comms.swarm_link import SwarmLink
from comms.zenoh_session import ZenohOpenError, ZenohSession
from gcs.dashboard.gcs_link import GcsDashboardLink, start_dashboard_process
from gcs.processes.event_log import EventLog
from gcs.processes.fleet_readiness import (HeartbeatWatch, everyone_heard, everyone_in_offboard, startup_problem,
                                           takeoff_problem)
from gcs.processes.ground_radio import GroundRadio
from gcs.processes.intrusion_watch import IntrusionWatch
from gcs.processes.host_capacity import host_warning
from gcs.processes.launch import ProcessOptions, hub_config
from gcs.processes.live_view import LiveOutput, station_snapshot
from gcs.processes.lost_vehicles import LostVehicles
from gcs.processes.mavlink_watch import MavlinkWatcher
from gcs.processes.mission_children import ChildFailed, MissionChildren, StartupProgress
from gcs.processes.mission_phase import MissionPhase, PhaseFailure, PhaseObservation, PhaseState, next_phase
from gcs.processes.mission_summary import note_refused_copies, print_summary, write_outputs
from gcs.processes.pace_watch import ClockStalled, PaceWatch
from gcs.processes.polygon_publisher import PolygonPublisher
from gcs.processes.recorder import MissionRecorder
from gcs.processes.run_verdict import EngineHealth, engine_verdict
from gcs.processes.sim_evaluation import SimulationEvaluation
from gcs.processes.supervisor import Supervisor
from gcs.scenario import Scenario
from mission_plan.roles import Role

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_INTERRUPTED = 130
_AIRBORNE_FRACTION = 0.8
_COMMAND_REPEAT_S = 0.5
_SNAPSHOT_PERIOD_S = 5.0

class MissionFailed(RuntimeError):
    """The mission cannot go on; the message is the one line the user sees."""


class GroundStation:
    def __init__(self, scenario: Scenario, options: ProcessOptions, out_dir: Path, console: Console | None = None,
                 simulated: bool = True) -> None:
        self.scenario = scenario
        self.options = options
        self.out_dir = out_dir
        self.mission = options.mission or scenario.name
        self.keys = MissionKeys(self.mission)
        self.console = console or Console(stderr=False)
        self.duration_s = options.duration_s if options.duration_s is not None else scenario.duration_s
        self.vehicle_ids = [v.vehicle_id for v in scenario.vehicles]
        self.roles = {v.vehicle_id: v.role for v in scenario.vehicles}
        self.groups = {v.vehicle_id: v.group or "" for v in scenario.vehicles}
        self.recorder = MissionRecorder(scenario.name, options.mode, scenario.seed, self.vehicle_ids,
                                        [self.roles[v] for v in self.vehicle_ids])
        self.evaluation: SimulationEvaluation | None = (
            SimulationEvaluation(scenario, self.duration_s, self.vehicle_ids, self.recorder) if simulated else None)
        self.phase_state = PhaseState()
        self.mission_t_s = 0.0
        self.flood_clock_start_s: float | None = None
        self.states: dict[int, NeighbourState] = {}
        self.agent_alive: dict[int, bool] = {}
        self.losses = LostVehicles()
        leader_id = next((v.vehicle_id for v in scenario.vehicles if v.role == Role.LEADER and v.has_gps), None)
        self.polygon = PolygonPublisher(self.keys, self.mission, scenario.home, scenario.control_params(options.mode).ring_order(),
                                        leader_id, scenario.control_rate_hz, self.recorder.polygons)
        self.events = EventLog(out_dir / "events.log", lambda: self.mission_t_s)
        self.startup = StartupProgress()
        self.children: MissionChildren | None = (
            MissionChildren(scenario, options, out_dir, self.mission, self.events) if simulated else None)
        self.supervisor = self.children.supervisor if self.children is not None else Supervisor(out_dir)
        """Every process the station starts (the simulation's and the live map's) is one of its children."""
        self.key_path: Path | None = options.key_file
        self.mission_key: MissionKey | None = None
        self.intrusions: IntrusionWatch | None = None
        self.radio: GroundRadio | None = None
        self.dashboard: GcsDashboardLink | None = None
        self.flood_start_utc: dt.datetime | None = None
        self.pace = PaceWatch(self.keys, options.agent_timeout_s, self.events)
        self.failsafes: list[str] = []
        self._interrupted = False
        self.heartbeats = HeartbeatWatch(options.speed)
        self._command_seq = 0
        self._next_polygon_t_s = 0.0
        self._next_command_s = 0.0

    @property
    def phase(self) -> MissionPhase:
        return self.phase_state.phase

    # ------------------------------------------------------------------ life cycle
    async def run(self) -> int:
        loop = asyncio.get_running_loop()
        for sig in (signal.SIGINT, signal.SIGTERM):
            try:
                loop.add_signal_handler(sig, self.interrupt)
            except (RuntimeError, ValueError):  # not the main thread (a test runs the mission in a thread)
                break
        code = EXIT_FAILED
        hub: ZenohSession | None = None
        watcher: MavlinkWatcher | None = None
        try:
            self.events(f"mission {self.mission}: scenario {self.scenario.name}, mode {self.options.mode}, seed "
                        f"{self.scenario.seed}, {len(self.vehicle_ids)} vehicles, speed x{self.options.speed:g}, "
                        f"duration {self.duration_s:g} s, output {self.out_dir}")
            self._warn_if_host_too_small()
            hub = self._open_hub()
            watcher = MavlinkWatcher(self.out_dir, self.events)
            try:
                await watcher.open("127.0.0.1", self.options.gcs_port)
            except OSError as exc:
                raise MissionFailed(str(exc.strerror or exc)) from None
            if self.children is not None:
                self.children.start(self.states)
                self.agent_alive.update((vid, False) for vid in self.children.expected_agents)
                self.key_path, self.mission_key = self.children.key_path, self.children.mission_key
            else:
                self.mission_key = self._read_key()
                self.agent_alive.update((vid, False) for vid in self.vehicle_ids)
                self.events("no simulator: watching the vehicles on the GCS link and the agents over Zenoh")
            self.dashboard = GcsDashboardLink(self, hub, lambda command: self._command(hub, command),
                                              self.heartbeats.lost_after_s)
            start_dashboard_process(self)
            code = await self._watch(hub, watcher)
        except (MissionFailed, ChildFailed, ClockStalled) as exc:
            self.events(f"mission failed: {exc}")
            self.console.print(f"[bold red]mission failed:[/] {exc}")
            code = EXIT_FAILED
        except Exception as exc:  # noqa: BLE001 - a bug here must still stop every child and keep the record
            (self.out_dir / "gcs_error.log").write_text(traceback.format_exc())
            self.events(f"ground station error: {exc!r} (traceback in gcs_error.log)")
            self.console.print(f"[bold red]ground station error:[/] {exc!r} (traceback in {self.out_dir / 'gcs_error.log'})")
            code = EXIT_FAILED
        finally:
            if self.children is not None:
                self.children.stop_all()
            else:
                self.supervisor.stop_all()
            if watcher is not None:
                self.failsafes = list(watcher.failsafes)
                watcher.close()
            if hub is not None:
                hub.close()
            self.polygon.close()
            code = self._finish(code)
            self.events.close()
        return code

    def _warn_if_host_too_small(self) -> None:
        warning = host_warning(len(self.vehicle_ids), self.scenario.control_rate_hz, self.options.speed,
                               paced=self.options.clock == "paced")
        if warning is not None:
            self.events(warning)
            self.console.print(f"[bold yellow]{warning}[/]")

    def interrupt(self) -> None:
        """Stop the mission as Ctrl-C does (thread-safe: the loop polls the flag)."""
        self._interrupted = True

    def _read_key(self) -> MissionKey:
        """The mission key the agents sign with, from ``--key-file`` (without a simulator nobody writes one)."""
        if self.key_path is None:
            raise MissionFailed("--key-file: required without a simulator (the agents' mission key)")
        try:
            return read_key_file(self.key_path)
        except KeyFileError as exc:
            raise MissionFailed(str(exc)) from None

    def _open_hub(self) -> ZenohSession:
        try:
            return ZenohSession(hub_config(self.options))
        except ZenohOpenError as exc:
            raise MissionFailed(f"Zenoh endpoint {self.options.zenoh_endpoint} is not free: {exc}") from None

    # ------------------------------------------------------------------ the loop
    async def _watch(self, hub: ZenohSession, watcher: MavlinkWatcher) -> int:
        simulated = self.evaluation is not None
        truth_buf = hub.subscribe(self.keys.truth) if simulated else None
        pace_buf = hub.subscribe(self.keys.pace_report) if simulated else None
        if pace_buf is not None:
            hub.subscribe(self.keys.camera_stats, pace_buf)
        assert self.mission_key is not None
        link = SwarmLink(hub, self.keys, None, via_radio=False, participant="gcs", key=self.mission_key, audit=True)
        self.intrusions = IntrusionWatch(hub, self.keys, self.mission_key, self.events, lambda: self.mission_t_s)
        self.radio = GroundRadio.for_scenario(self.scenario, hub, self.keys, self.mission_key) if simulated else None
        started_wall_s = time.monotonic()
        self.pace.clock_moved(self.mission_t_s, started_wall_s)
        tick_s = min(0.05, 1.0 / (self.scenario.control_rate_hz * self.options.speed))
        next_snapshot_s = 0.0
        with LiveOutput(self.console, self.options.live) as view:
            while True:
                await asyncio.sleep(tick_s)
                now_wall_s = time.monotonic()
                self._check_vehicles(watcher, now_wall_s)
                if self._interrupted:
                    self.events("interrupted (Ctrl-C / SIGTERM): stopping every process")
                    self.console.print("[bold yellow]interrupted:[/] stopping every process, writing what was recorded")
                    return EXIT_INTERRUPTED
                if truth_buf is not None and self.evaluation is not None:
                    self.mission_t_s = self.evaluation.poll_truth(truth_buf, self.mission_t_s)
                self._poll_swarm(link)
                if self.radio is not None:
                    self.radio.poll(self.mission_t_s)
                self.polygon.remember(self.states if self.radio is None else self.radio.heard, self.mission_t_s)
                self.intrusions.poll(now_wall_s)
                if pace_buf is not None:
                    self.pace.poll(pace_buf)
                self.pace.check_clock_moves(self.mission_t_s, self.phase.in_flight, now_wall_s)
                self._check_children()
                if self.dashboard is not None:
                    self.dashboard.tick(watcher, now_wall_s)
                if self._advance(hub, watcher, now_wall_s, started_wall_s):
                    await asyncio.sleep(max(0.2, 2 * tick_s))
                    return EXIT_OK
                if now_wall_s >= next_snapshot_s and len(self.recorder):
                    self.recorder.save_snapshot(self.out_dir / "record.npz")
                    next_snapshot_s = now_wall_s + _SNAPSHOT_PERIOD_S
                if view.due(now_wall_s):
                    view.show(station_snapshot(self, watcher, now_wall_s), now_wall_s)

    def _advance(self, hub: ZenohSession, watcher: MavlinkWatcher, now_wall_s: float, started_wall_s: float) -> bool:
        """The phase's work, one step of the phase machine, and the orders that follow; True once the mission is
        complete (the vehicles were told to hold)."""
        if self.phase is MissionPhase.STARTING and self.children is not None:
            self.agent_alive.update((vid, False) for vid in self.children.start_agents(self.states))
        elif self.phase is MissionPhase.MISSION:
            flood_t_s = self.flood_time_s()
            if self.evaluation is not None:
                self.evaluation.record(self.flood_clock_start_s or 0.0, self.lost)
            if flood_t_s >= self._next_polygon_t_s:
                self._polygon(hub, flood_t_s)
                self._next_polygon_t_s += self.scenario.polygon_period_s
        step = next_phase(self.phase_state, self._observe(watcher, now_wall_s, started_wall_s))
        self.phase_state = step.state
        if step.failure is PhaseFailure.STARTUP_STALLED:
            raise MissionFailed(startup_problem(
                self.vehicle_ids, watcher.vehicles, self.states, self.agent_alive, self.children,
                truth_missing=self.evaluation is not None and self.evaluation.truth is None,
                gcs_port=self.options.gcs_port, timeout_s=self.options.startup_timeout_s,
                connected=self.startup.connected))
        if step.failure is PhaseFailure.TAKEOFF_TIMEOUT:
            raise MissionFailed(takeoff_problem(watcher.vehicles, self.lost, self.options.takeoff_timeout_s))
        if step.entered is MissionPhase.TAKEOFF:
            self.events(f"all {len(self.vehicle_ids)} vehicles and agents up after "
                        f"{now_wall_s - started_wall_s:.1f} s: taking off")
        elif step.entered is MissionPhase.MISSION:
            self._start_flood_clock()
            self._next_command_s = 0.0
        elif step.entered is MissionPhase.DONE:
            self.events(f"flood clock reached {self.duration_s:g} s: mission complete, vehicles hold")
            self._command(hub, "hold")
            return True
        if now_wall_s >= self._next_command_s and self.phase.in_flight:
            default = "start" if self.phase is MissionPhase.MISSION else "phase"
            self._command(hub, self.dashboard.command_for(default) if self.dashboard else default)
            self._next_command_s = now_wall_s + _COMMAND_REPEAT_S
        return False

    def _observe(self, watcher: MavlinkWatcher, now_wall_s: float, started_wall_s: float) -> PhaseObservation:
        """What the phase machine needs this loop (each check only in the phase that reads it)."""
        starting = self.phase is MissionPhase.STARTING
        return PhaseObservation(
            everyone_up=starting and self._everyone_up(watcher),
            everyone_in_offboard=self.phase is MissionPhase.TAKEOFF and everyone_in_offboard(
                self.vehicle_ids, self.lost, watcher.vehicles, _AIRBORNE_FRACTION * self.scenario.altitude_m),
            mission_t_s=self.mission_t_s, flood_t_s=self.flood_time_s(), duration_s=self.duration_s,
            startup_idle_s=now_wall_s - self._last_startup_progress_wall_s(started_wall_s) if starting else 0.0,
            startup_timeout_s=self.options.startup_timeout_s, takeoff_timeout_s=self.options.takeoff_timeout_s,
        )

    def _start_flood_clock(self) -> None:
        self.flood_clock_start_s = self.mission_t_s
        self.flood_start_utc = dt.datetime.now(dt.timezone.utc)
        self.polygon.start_log(self.out_dir, self.flood_start_utc)
        self.events("every vehicle airborne in OFFBOARD: flood clock starts, mission start")

    def flood_time_s(self) -> float:
        """Flood clock [s]: 0 until every vehicle is airborne in OFFBOARD, then mission time since."""
        return 0.0 if self.flood_clock_start_s is None else self.mission_t_s - self.flood_clock_start_s

    def _command(self, hub: ZenohSession, command: str) -> None:
        self._command_seq += 1
        msg = MissionCommand(seq=self._command_seq, t_s=self.mission_t_s, command=command,  # type: ignore[arg-type]
                             phase=self.phase.value, flood_clock_start_t_s=self.flood_clock_start_s)
        assert self.intrusions is not None
        hub.put(self.keys.command, self.intrusions.sign_command(encode(msg)))

    def _last_startup_progress_wall_s(self, started_wall_s: float) -> float:
        expected = self.children.expected_agents if self.children is not None else self.vehicle_ids
        return self.startup.last_progress_wall_s(started_wall_s, sum(1 for vid in expected if vid in self.states))

    # ------------------------------------------------------------------ what is going on
    def _poll_swarm(self, link: SwarmLink) -> None:
        update = link.poll()
        if self.intrusions is not None:
            self.intrusions.observe_states(update.rejected)
        for state in update.states:
            old = self.states.get(state.sender_id)
            if old is None or state.seq > old.seq:
                self.states[state.sender_id] = state
            if self.evaluation is None:  # no simulator: the agents' mission clock is the clock
                self.mission_t_s = max(self.mission_t_s, state.t_s)
            if state.encircle_complete and self.recorder.encircle_time_s is None and self.phase is MissionPhase.MISSION:
                self.recorder.encircle_time_s = self.flood_time_s()
                self.events(f"encircling complete (reported by vehicle {state.sender_id}) at flood time "
                            f"{self.recorder.encircle_time_s:.1f} s")
        for vid in update.alive:
            if vid in self.agent_alive and not self.agent_alive[vid]:
                self.agent_alive[vid] = True
        for vid in update.dead:
            if self.agent_alive.get(vid):
                self.agent_alive[vid] = False
                self.events(f"agent {vid} lost: its liveliness token is gone")
                self.losses.agent_gone(vid, self.flood_time_s())

    def _check_children(self) -> None:
        if self.children is None:
            return
        for vid, code, child in self.children.newly_exited_agents():
            if self.phase in (MissionPhase.STARTING, MissionPhase.TAKEOFF):
                raise MissionFailed(f"agent {vid} failed to start (exit code {code}): {child.log_tail(2)}")
            self.events(f"agent {vid} exited with code {code}")
            self.losses.agent_gone(vid, self.flood_time_s())

    def _check_vehicles(self, watcher: MavlinkWatcher, now_wall_s: float) -> None:
        if not self.phase.in_flight:
            return
        changes = self.heartbeats.changes(self.vehicle_ids, watcher.vehicles, now_wall_s)
        if self.heartbeats.spared:
            self.events(f"ground station did not run for {self.heartbeats.own_stall_s:.1f} s (host under load): "
                        f"vehicles {', '.join(map(str, self.heartbeats.spared))} looked silent; judged again once it "
                        f"has read its link")
        for vid, silent, lost_after_s in changes:
            if silent:
                self.events(f"vehicle {vid} lost: no heartbeat on the GCS link for {lost_after_s:g} s")
                self.losses.link_silent(vid, self.flood_time_s())
            elif self.losses.link_back(vid):
                self.events(f"vehicle {vid}: heartbeat back on the GCS link, counted again")
            else:
                self.events(f"vehicle {vid}: heartbeat back on the GCS link")

    @property
    def lost(self) -> dict[int, float]:
        """The vehicles lost now, each with the flood time it was lost at (:class:`LostVehicles`)."""
        return self.losses.since_flood_s

    def _everyone_up(self, watcher: MavlinkWatcher) -> bool:
        heard = everyone_heard(self.vehicle_ids, watcher.vehicles)
        connected = all(vid in self.states for vid in self.vehicle_ids)  # agents publish once their autopilot answers
        truth_ok = self.evaluation is None or self.evaluation.truth is not None
        return heard and connected and all(self.agent_alive.values()) and truth_ok

    # ------------------------------------------------------------------ recording and the polygon
    def _polygon(self, hub: ZenohSession, flood_t_s: float) -> None:
        heard = self.states if self.radio is None else self.radio.heard
        ring = self.polygon.publish(hub, heard, self.lost, self.mission_t_s, flood_t_s)
        if self.evaluation is not None:
            self.evaluation.measure(ring, flood_t_s)

    # ------------------------------------------------------------------ view and outputs
    def _finish(self, code: int) -> int:
        """Write the outputs and the verdicts; returns the exit code (``--strict``: 1 on a degraded engine)."""
        engine = engine_verdict(self.pace.pace_report, self.pace.camera_stats, self.vehicle_ids, self.scenario.control_rate_hz,
                                self.options.clock, cameras_expected=Role.BOUNDARY in self.roles.values())
        self.events(engine.text())
        if code == EXIT_OK and self.options.strict and engine.health is EngineHealth.DEGRADED:
            code = EXIT_FAILED
        note_refused_copies(self.recorder, self.children, self.radio, self.events)
        self.recorder.events = list(self.events.entries)
        flood = self.evaluation.flood if self.evaluation is not None else None
        if write_outputs(self.recorder, flood, self.scenario, self.out_dir, self.flood_start_utc, self.console, engine):
            print_summary(self.out_dir, code == EXIT_OK, engine, self.failsafes, self.events, self.console)
        return code
