"""The process engine's ground station: starts the mission's processes, watches them, records, reports.

Sequence (SPEC §1, §6):

1. open the mission's Zenoh hub (the port outside clients join) and the MAVLink GCS port, so a busy port fails
   before any child starts;
2. write each child's plan file (``<out>/plan/``: fleet, cameras, one per agent), then start the mock fleet with its
   simulator bridge, the camera renderer, the radio emulator, and one agent process per vehicle;
3. STARTING: start the agents a few at a time (four per core of the machine still connecting:
   200 interpreters importing at once would starve the ones already up past their link watchdogs), and wait until
   every vehicle is heard on the GCS link and every agent holds its liveliness token;
4. TAKEOFF: the agents arm, take off and switch to OFFBOARD on their own; when the GCS link shows every vehicle
   armed, airborne and in OFFBOARD, the ground station starts the flood clock and commands ``start``;
5. MISSION: records ground truth, aggregates and publishes the caged polygon, reports vehicles and agents lost;
6. at the end of the flood clock it commands ``hold``, stops every process and writes the outputs, with two
   verdicts (:mod:`gcs.processes.run_verdict`): engine health from the simulator's pace report and the cameras'
   frame rate, and safety from the failsafes announced and the closest approach.

The simulation clock is paced by default (``--clock paced``, :mod:`mock_autopilot.pacing`): the fleet holds each
control tick until every live agent, the cameras and the radio have acknowledged it. Watchdogs stay on the wall
clock (the vehicles' heartbeats go on while simulated time stands still), so a slow paced run is never a lost link.

Any failure (a child that dies early, a timeout, Ctrl-C) ends the run with one clear message and a non-zero exit
code; every path stops every child and writes what was recorded.
"""

from __future__ import annotations

import asyncio
import datetime as dt
import json
import math
import os
import signal
import sys
import time
import traceback
from collections.abc import Mapping
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.live import Live

from comms.keys import MissionKeys
from comms.latest_buffer import LatestValueBuffer
from comms.messages import (
    FLAG_SEES_EDGE,
    CameraStats,
    GroundTruth,
    MissionCommand,
    NeighbourState,
    PaceReport,
    decode,
    encode,
    flood_polygon_from_enu,
)
from comms.key_file import KeyFileError, read_key_file
from comms.radio_model import GROUND_NODE_ID
from comms.signing import MissionKey, Verifier
from comms.swarm_link import SwarmLink, bundle_unpacker, wall_clock_us
from comms.zenoh_session import ZenohConfig, ZenohOpenError, ZenohSession
from gcs.dashboard.gcs_link import GcsDashboardLink, start_dashboard_process
from gcs.metrics.coverage import CoverageGrid, footprint_coverage
from gcs.metrics.polygon_quality import polygon_iou
from gcs.mission_record import PolygonSample
from gcs.polygon.growth import polygon_growth_rate_m2ps
from gcs.processes.event_log import EventLog
from gcs.processes.host_capacity import agent_niceness, estimate_capacity
from gcs.processes.intrusion_watch import IntrusionWatch
from gcs.plan.files import write_plans
from gcs.processes.launch import ProcessOptions, agent_command, cameras_command, radio_command, sim_command
from gcs.processes.link_silence import SilenceJudge
from gcs.processes.live_view import MissionSnapshot, VehicleRow, render, status_line
from gcs.processes.mavlink_watch import MavlinkWatcher
from gcs.polygon.radio_node import GroundNode, antenna_enu_m
from gcs.polygon.reports import aggregate_polygon, georeference_offset_en_m, report_max_age_s
from gcs.processes.recorder import MissionRecorder
from gcs.processes.run_verdict import EngineHealth, EngineVerdict, engine_verdict, safety_verdict
from gcs.processes.supervisor import Child, Supervisor
from gcs.report import write_mission_outputs
from gcs.report.outputs import write_metrics_json
from gcs.report.polygon_log import PolygonLog
from gcs.scenario import Scenario
from mock_autopilot.world.config import flood_model_from_config

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_INTERRUPTED = 130
VEHICLE_LOST_AFTER_S = 2.0
"""Wall seconds without a heartbeat on the GCS link before a vehicle is reported lost (SPEC §7: within 2 s)."""


def vehicle_lost_after_s(speed: float) -> float:
    """Heartbeat silence [wall s] that counts as a lost vehicle at simulation speed ``speed``: two heartbeat
    periods. The mock PX4 beats at 1 Hz of simulated time, so below real time (``--speed`` < 1) its heartbeats
    come further apart on the wall clock and the bound widens with them; at or above real time it stays at SPEC
    §7's 2 s."""
    return VEHICLE_LOST_AFTER_S / min(1.0, speed)
_AIRBORNE_FRACTION = 0.8
_COMMAND_REPEAT_S = 0.5
_SNAPSHOT_PERIOD_S = 5.0
_VIEW_PERIOD_S = 0.25
_STATUS_LINE_PERIOD_S = 5.0
CLOCK_STALL_WALL_S = 60.0
"""Wall seconds without the mission clock moving, in flight, after which the run fails: the paced clock waits for
the cameras and the radio as long as they live, so a hung one must still end the run."""


class MissionFailed(RuntimeError):
    """The mission cannot go on; the message is the one line the user sees."""


class GroundStation:
    def __init__(self, scenario: Scenario, options: ProcessOptions, out_dir: Path, console: Console | None = None) -> None:
        self.scenario = scenario
        self.options = options
        self.out_dir = out_dir
        self.mission = options.mission or scenario.name
        self.keys = MissionKeys(self.mission)
        self.console = console or Console(stderr=False)
        self.duration_s = options.duration_s if options.duration_s is not None else scenario.duration_s
        self.params = scenario.control_params(options.mode)
        self.ring_order = [vid for vid in self.params.ring_order()]
        self.vehicle_ids = [v.vehicle_id for v in scenario.vehicles]
        self.roles = {v.vehicle_id: v.role for v in scenario.vehicles}
        self.groups = {v.vehicle_id: v.group or "" for v in scenario.vehicles}
        self.leader_id = next((v.vehicle_id for v in scenario.vehicles if v.role == "leader" and v.has_gps), None)
        self.flood = flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
        self.recorder = MissionRecorder(scenario.name, options.mode, scenario.seed, self.vehicle_ids,
                                        [self.roles[v] for v in self.vehicle_ids])
        self.phase = "starting"
        self.mission_t_s = 0.0
        self.flood_clock_start_s: float | None = None
        self.truth: GroundTruth | None = None
        self.states: dict[int, NeighbourState] = {}
        self.radio_node = None if scenario.radio.gcs_lossless else GroundNode(
            antenna_enu_m(np.array([v.pad_enu_m for v in scenario.vehicles], dtype=float)))
        """The ground station as a radio node: the polygon is built from what reaches its antenna (the public
        state keys still serve supervision: who is up, who is lost)."""
        self.agent_alive: dict[int, bool] = {}
        self.lost: dict[int, float] = {}
        self.polygon_iou = math.nan
        self.coverage = math.nan
        self.polygon_area_m2 = math.nan
        self.events = EventLog(out_dir / "events.log", lambda: self.mission_t_s)
        self.supervisor = Supervisor(out_dir)
        self.agents: dict[int, Child] = {}
        self._agents_to_start: list[int] = []
        self._startup_connected = 0
        self._startup_progress_wall_s = 0.0
        self._agent_plans: Mapping[int, Path] = {}
        self.services: dict[str, Child] = {}
        self.flood_start_utc: dt.datetime | None = None
        self.polygon_log: PolygonLog | None = None
        self.pace_report: PaceReport | None = None
        self.camera_stats: CameraStats | None = None
        self._left_behind_counts: dict[str, int] = {}
        self.failsafes: list[str] = []
        self._interrupted = False
        self._exited_agents: set[int] = set()
        self._silence = SilenceJudge(vehicle_lost_after_s(options.speed))
        self._command_seq = 0
        self.mission_key: MissionKey | None = None
        self._node_verifier: Verifier | None = None
        self.intrusions: IntrusionWatch | None = None
        self._next_polygon_t_s = 0.0
        self.dashboard: GcsDashboardLink | None = None
        self._grid = CoverageGrid.around(*_flood_box(self.flood, self.duration_s), max_cells_per_side=100)

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
            self.dashboard = GcsDashboardLink(self, hub, lambda command: self._command(hub, command),
                                              vehicle_lost_after_s(self.options.speed))
            start_dashboard_process(self)
            watcher = MavlinkWatcher(self.out_dir, self.events)
            try:
                await watcher.open("127.0.0.1", self.options.gcs_port)
            except OSError as exc:
                raise MissionFailed(str(exc.strerror or exc)) from None
            self._start_children()
            code = await self._watch(hub, watcher)
        except MissionFailed as exc:
            self.events(f"mission failed: {exc}")
            self.console.print(f"[bold red]mission failed:[/] {exc}")
            code = EXIT_FAILED
        except Exception as exc:  # noqa: BLE001 - a bug here must still stop every child and keep the record
            (self.out_dir / "gcs_error.log").write_text(traceback.format_exc())
            self.events(f"ground station error: {exc!r} (traceback in gcs_error.log)")
            self.console.print(f"[bold red]ground station error:[/] {exc!r} (traceback in {self.out_dir / 'gcs_error.log'})")
            code = EXIT_FAILED
        finally:
            self.supervisor.stop_all()
            self._report_exits()
            if watcher is not None:
                self.failsafes = list(watcher.failsafes)
                watcher.close()
            if hub is not None:
                hub.close()
            if self.polygon_log is not None:
                self.polygon_log.close()
            code = self._finish(code)
            self.events.close()
        return code

    def _warn_if_host_too_small(self) -> None:
        estimate = estimate_capacity(len(self.vehicle_ids), self.scenario.control_rate_hz, self.options.speed,
                                     len(os.sched_getaffinity(0)))
        warning = estimate.warning(len(self.vehicle_ids), self.scenario.control_rate_hz, self.options.speed,
                                   paced=self.options.clock == "paced")
        if warning is not None:
            self.events(warning)
            self.console.print(f"[bold yellow]{warning}[/]")

    def interrupt(self) -> None:
        """Stop the mission as Ctrl-C does (thread-safe: the loop polls the flag)."""
        self._interrupted = True

    def _open_hub(self) -> ZenohSession:
        try:
            return ZenohSession(ZenohConfig.hub(self.options.zenoh_endpoint))
        except ZenohOpenError as exc:
            raise MissionFailed(f"Zenoh endpoint {self.options.zenoh_endpoint} is not free: {exc}") from None

    def _start_children(self) -> None:
        opts = self.options
        try:
            plans = write_plans(self.scenario, opts.mode, (self.out_dir / "plan").resolve(), self.mission, opts.key_file)
            self.mission_key = read_key_file(plans.key)
        except KeyFileError as exc:
            raise MissionFailed(str(exc)) from None
        self.services["sim"] = self.supervisor.start("sim", sim_command(opts, plans.fleet))
        self.services["cameras"] = self.supervisor.start("cameras", cameras_command(opts, plans.cameras))
        self.services["radio"] = self.supervisor.start("radio", radio_command(opts, self.scenario, self.mission, plans.key))
        self._agent_plans = plans.agents
        self._agents_to_start = [v.vehicle_id for v in self.scenario.vehicles]
        self._write_pids()
        self.events(f"started the fleet+truth, cameras and radio processes; {len(self._agents_to_start)} agents "
                    f"follow, {self._max_agents_connecting()} at a time (logs in {self.out_dir})")
        self._start_agents()

    def _max_agents_connecting(self) -> int:
        return 4 * len(os.sched_getaffinity(0))

    def _start_agents(self) -> None:
        """Start the next agents while fewer than :meth:`_max_agents_connecting` are still connecting."""
        connecting = sum(1 for vid in self.agents if vid not in self.states)
        started = 0
        while self._agents_to_start and connecting < self._max_agents_connecting():
            vid = self._agents_to_start.pop(0)
            self.agents[vid] = self.supervisor.start(
                f"agent_{vid}", agent_command(self.options, vid, self._agent_plans[vid], len(self.vehicle_ids)),
                niceness=agent_niceness(len(self.vehicle_ids)),
            )
            self.agent_alive[vid] = False
            connecting += 1
            started += 1
        if started:
            self._write_pids()
            if not self._agents_to_start:
                self.events(f"all {len(self.agents)} agents started")

    def _write_pids(self) -> None:
        pids = {child.name: child.pid for child in self.supervisor.children}
        (self.out_dir / "processes.json").write_text(json.dumps(pids, indent=1))

    # ------------------------------------------------------------------ the loop
    async def _watch(self, hub: ZenohSession, watcher: MavlinkWatcher) -> int:
        truth_buf = hub.subscribe(self.keys.truth)
        pace_buf = hub.subscribe(self.keys.pace_report)
        hub.subscribe(self.keys.camera_stats, pace_buf)
        assert self.mission_key is not None
        link = SwarmLink(hub, self.keys, None, via_radio=False, participant="gcs", key=self.mission_key, audit=True)
        self.intrusions = IntrusionWatch(hub, self.keys, self.mission_key, self.events, lambda: self.mission_t_s)
        node_buf = None if self.radio_node is None else hub.subscribe(
            self.keys.inbox(GROUND_NODE_ID), LatestValueBuffer(), unpack=bundle_unpacker(self.keys))
        started_wall_s = time.monotonic()
        takeoff_deadline_s: float | None = None
        clock_seen = (self.mission_t_s, time.monotonic())
        tick_s = min(0.05, 1.0 / (self.scenario.control_rate_hz * self.options.speed))
        next_command_s = next_snapshot_s = next_view_s = 0.0
        next_status_s = time.monotonic() + _STATUS_LINE_PERIOD_S
        live = Live(console=self.console, refresh_per_second=4, transient=False) if self._use_live() else None
        if live is not None:
            live.start()
        try:
            while True:
                await asyncio.sleep(tick_s)
                now_wall_s = time.monotonic()
                self._check_vehicles(watcher, now_wall_s)
                if self._interrupted:
                    self.events("interrupted (Ctrl-C / SIGTERM): stopping every process")
                    self.console.print("[bold yellow]interrupted:[/] stopping every process, writing what was recorded")
                    return EXIT_INTERRUPTED
                for item in truth_buf.drain():
                    truth = decode(GroundTruth, item.payload)
                    if truth is not None and (self.truth is None or truth.t_s >= self.truth.t_s):
                        self.truth = truth
                        self.mission_t_s = truth.t_s
                self._poll_swarm(link)
                if node_buf is not None:
                    self._poll_radio_node(node_buf)
                self.intrusions.poll(now_wall_s)
                self._poll_pace(pace_buf)
                clock_seen = self._check_clock_moves(clock_seen, now_wall_s)
                self._check_children()
                if self.dashboard is not None:
                    self.dashboard.tick(watcher, now_wall_s)
                if self.phase == "starting":
                    self._start_agents()
                    if self._everyone_up(watcher):
                        self.phase = "takeoff"
                        takeoff_deadline_s = self.mission_t_s + self.options.takeoff_timeout_s
                        self.events(f"all {len(self.vehicle_ids)} vehicles and agents up after "
                                    f"{now_wall_s - started_wall_s:.1f} s: taking off")
                    elif (now_wall_s - self._last_startup_progress_wall_s(started_wall_s)
                          > self.options.startup_timeout_s):
                        raise MissionFailed(self._startup_problem(watcher))
                elif self.phase == "takeoff":
                    if self._everyone_in_offboard(watcher):
                        self.phase = "mission"
                        self.flood_clock_start_s = self.mission_t_s
                        self.flood_start_utc = dt.datetime.now(dt.timezone.utc)
                        self.polygon_log = PolygonLog(self.out_dir, self.scenario.home, start_utc=self.flood_start_utc)
                        self.events("every vehicle airborne in OFFBOARD: flood clock starts, mission start")
                        next_command_s = 0.0
                    elif takeoff_deadline_s is not None and self.mission_t_s > takeoff_deadline_s:
                        raise MissionFailed(self._takeoff_problem(watcher))
                elif self.phase == "mission":
                    self._record(watcher)
                    flood_t_s = self.flood_time_s()
                    if flood_t_s >= self._next_polygon_t_s:
                        self._polygon(hub, flood_t_s)
                        self._next_polygon_t_s += self.scenario.polygon_period_s
                    if flood_t_s >= self.duration_s:
                        self.phase = "done"
                        self.events(f"flood clock reached {self.duration_s:g} s: mission complete, vehicles hold")
                        self._command(hub, "hold")
                        await asyncio.sleep(max(0.2, 2 * tick_s))
                        return EXIT_OK
                if now_wall_s >= next_command_s and self.phase in ("takeoff", "mission"):
                    default = "start" if self.phase == "mission" else "phase"
                    self._command(hub, self.dashboard.command_for(default) if self.dashboard else default)
                    next_command_s = now_wall_s + _COMMAND_REPEAT_S
                if now_wall_s >= next_snapshot_s and len(self.recorder):
                    self.recorder.save_snapshot(self.out_dir / "record.npz")
                    next_snapshot_s = now_wall_s + _SNAPSHOT_PERIOD_S
                if now_wall_s >= next_view_s:
                    snapshot = self._snapshot(watcher, now_wall_s)
                    if live is not None:
                        live.update(render(snapshot))
                    elif now_wall_s >= next_status_s:
                        print(status_line(snapshot), flush=True)
                        next_status_s = now_wall_s + _STATUS_LINE_PERIOD_S
                    next_view_s = now_wall_s + _VIEW_PERIOD_S
        finally:
            if live is not None:
                live.stop()

    def _use_live(self) -> bool:
        return self.options.live and self.console.is_terminal

    def flood_time_s(self) -> float:
        """Flood clock [s]: 0 until every vehicle is airborne in OFFBOARD, then mission time since."""
        return 0.0 if self.flood_clock_start_s is None else self.mission_t_s - self.flood_clock_start_s

    def _command(self, hub: ZenohSession, command: str) -> None:
        self._command_seq += 1
        msg = MissionCommand(seq=self._command_seq, t_s=self.mission_t_s, command=command,  # type: ignore[arg-type]
                             phase=self.phase, flood_clock_start_t_s=self.flood_clock_start_s)
        assert self.intrusions is not None
        hub.put(self.keys.command, self.intrusions.sign_command(encode(msg)))

    def _check_clock_moves(self, seen: tuple[float, float], now_wall_s: float) -> tuple[float, float]:
        """Fail the run when the mission clock has stood still for :data:`CLOCK_STALL_WALL_S` in flight."""
        if self.mission_t_s != seen[0] or self.phase not in ("takeoff", "mission"):
            return self.mission_t_s, now_wall_s
        if now_wall_s - seen[1] > CLOCK_STALL_WALL_S:
            waiting = ", ".join(self.pace_report.waiting_for) if self.pace_report else "unknown"
            raise MissionFailed(f"the simulation clock has stood at {self.mission_t_s:.2f} s for "
                                f"{CLOCK_STALL_WALL_S:g} s of wall time (waiting for: {waiting})")
        return seen

    def _last_startup_progress_wall_s(self, started_wall_s: float) -> float:
        """When start-up last moved on: the start, or the newest agent that connected. Start-up fails when it
        stalls for ``startup_timeout_s``, not when it is merely slow (208 agents on 2 busy cores came up at one
        per 3 s, ten minutes in all)."""
        connected = sum(1 for vid in self.agents if vid in self.states)
        if connected != self._startup_connected:
            self._startup_connected = connected
            self._startup_progress_wall_s = time.monotonic()
        return max(started_wall_s, self._startup_progress_wall_s)

    # ------------------------------------------------------------------ what is going on
    def _poll_pace(self, buf: LatestValueBuffer) -> None:
        """The simulator's pace report and the cameras' frame rate; an agent newly left behind is an event."""
        for item in buf.drain():
            if item.key == self.keys.pace_report:
                report = decode(PaceReport, item.payload)
                if report is None:
                    continue
                self.pace_report = report
                for p in report.participants:
                    if p.times_left_behind > self._left_behind_counts.get(p.participant, 0):
                        self.events(f"{'agent ' if p.participant.isdigit() else ''}{p.participant} left behind by the "
                                    f"paced clock (silent for {self.options.agent_timeout_s:g} s of wall time)")
                    self._left_behind_counts[p.participant] = p.times_left_behind
            else:
                stats = decode(CameraStats, item.payload)
                if stats is not None:
                    self.camera_stats = stats

    def _poll_swarm(self, link: SwarmLink) -> None:
        update = link.poll()
        if self.intrusions is not None:
            self.intrusions.observe_states(update.rejected)
        for state in update.states:
            old = self.states.get(state.sender_id)
            if old is None or state.seq > old.seq:
                self.states[state.sender_id] = state
            if state.encircle_complete and self.recorder.encircle_time_s is None and self.phase == "mission":
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
                self._mark_lost(vid)

    def _check_children(self) -> None:
        for name, child in self.services.items():
            code = child.exit_code()
            if code is not None:
                raise MissionFailed(f"{name} process exited with code {code}: {child.log_tail()}")
        for vid, child in self.agents.items():
            code = child.exit_code()
            if code is None or vid in self._exited_agents:
                continue
            self._exited_agents.add(vid)
            if self.phase in ("starting", "takeoff"):
                raise MissionFailed(f"agent {vid} failed to start (exit code {code}): {child.log_tail(2)}")
            self.events(f"agent {vid} exited with code {code}")
            self._mark_lost(vid)

    def _check_vehicles(self, watcher: MavlinkWatcher, now_wall_s: float) -> None:
        """Heartbeat silence on the GCS link (:mod:`gcs.processes.link_silence`), judged right after the loop's
        sleep, before this pass does any work of its own."""
        flying = self.phase in ("takeoff", "mission")
        ages = {vid: watcher.vehicles[vid].heartbeat_age_s(now_wall_s)
                for vid in self.vehicle_ids if vid in watcher.vehicles}
        verdict = self._silence.step(now_wall_s, ages, judging=flying)
        if verdict.spared:
            self.events(f"ground station did not run for {verdict.own_stall_s:.1f} s (host under load): vehicles "
                        f"{', '.join(map(str, verdict.spared))} looked silent; judged again once it has read its link")
        for vid in verdict.lost:
            self.events(f"vehicle {vid} lost: no heartbeat on the GCS link for {self._silence.lost_after_s:g} s")
            self._mark_lost(vid)
        for vid in verdict.back:
            self.events(f"vehicle {vid}: heartbeat back on the GCS link")

    def _mark_lost(self, vid: int) -> None:
        if vid not in self.lost:
            self.lost[vid] = self.flood_time_s()

    def _everyone_up(self, watcher: MavlinkWatcher) -> bool:
        heard = all(vid in watcher.vehicles and watcher.vehicles[vid].last_heartbeat_monotonic_s for vid in self.vehicle_ids)
        connected = all(vid in self.states for vid in self.vehicle_ids)  # agents publish once their autopilot answers
        return heard and connected and all(self.agent_alive.values()) and self.truth is not None

    def _everyone_in_offboard(self, watcher: MavlinkWatcher) -> bool:
        floor_m = _AIRBORNE_FRACTION * self.scenario.altitude_m
        for vid in self.vehicle_ids:
            if vid in self.lost:
                continue
            watch = watcher.vehicles.get(vid)
            if watch is None or watch.mode != "OFFBOARD" or not watch.armed or not watch.altitude_m >= floor_m:
                return False
        return True

    def _startup_problem(self, watcher: MavlinkWatcher) -> str:
        silent = [vid for vid in self.vehicle_ids if vid not in watcher.vehicles]
        no_agent = [vid for vid in self.vehicle_ids if not self.agent_alive.get(vid) or vid not in self.states]
        parts = []
        if silent:
            parts.append(f"no MAVLink from vehicles {silent} on GCS port {self.options.gcs_port}: "
                         f"{self.services['sim'].log_tail(2)}")
        if self._agents_to_start:
            parts.append(f"{len(self._agents_to_start)} agents not started yet (the ones before them were still "
                         f"connecting)")
        started_silent = [vid for vid in no_agent if vid in self.agents]
        if started_silent:
            parts.append(f"agents {started_silent} did not report over Zenoh: "
                         f"{self.agents[started_silent[0]].log_tail(2)}")
        if self.truth is None:
            parts.append("no ground truth from the simulator bridge")
        return (f"start-up stalled: nothing came up for {self.options.startup_timeout_s:g} s "
                f"({self._startup_connected} of {len(self.vehicle_ids)} agents connected): " + "; ".join(parts))

    def _takeoff_problem(self, watcher: MavlinkWatcher) -> str:
        late = [f"{vid} ({w.mode}, {'armed' if w.armed else 'disarmed'}, {w.altitude_m:.1f} m)"
                for vid, w in sorted(watcher.vehicles.items())
                if vid not in self.lost and (w.mode != "OFFBOARD" or not w.armed)]
        return f"vehicles not airborne in OFFBOARD after {self.options.takeoff_timeout_s:g} s: {', '.join(late[:6])}"

    # ------------------------------------------------------------------ recording and the polygon
    def _record(self, watcher: MavlinkWatcher) -> None:
        truth = self.truth
        if truth is None or truth.t_s < (self.flood_clock_start_s or 0.0):
            return
        index = {vid: i for i, vid in enumerate(truth.vehicle_ids)}
        n = len(self.vehicle_ids)
        positions = np.full((n, 3), np.nan)
        velocities = np.zeros((n, 3))
        alive = np.zeros(n, dtype=bool)
        for row, vid in enumerate(self.vehicle_ids):
            i = index.get(vid)
            if i is None:
                continue
            positions[row] = truth.positions_enu_m[i]
            if truth.velocities_enu_mps:
                velocities[row] = truth.velocities_enu_mps[i]
            alive[row] = (not truth.alive or truth.alive[i]) and vid not in self.lost
        sides = 2.0 * np.clip(positions[:, 2], 0.0, None) * math.tan(math.radians(self.scenario.camera.fov_deg) / 2.0)
        sides = np.where(alive & np.isfinite(sides), sides, 0.0)
        self.recorder.add(truth.t_s - (self.flood_clock_start_s or 0.0), positions, velocities, sides, alive)

    def _poll_radio_node(self, buffer: LatestValueBuffer) -> None:
        assert self.radio_node is not None and self.mission_key is not None
        if self._node_verifier is None:
            self._node_verifier = Verifier(self.mission_key)
        now_us = wall_clock_us()
        states = []
        for item in buffer.drain():
            if item.kind != "put":
                continue
            body = self._node_verifier.check(item.payload, self.keys.vehicle_id_of(item.key), now_us).body
            state = None if body is None else decode(NeighbourState, body)
            if state is not None:
                states.append(state)
        self.radio_node.hear(states, self.mission_t_s)

    def _polygon(self, hub: ZenohSession, flood_t_s: float) -> None:
        heard = self.states if self.radio_node is None else self.radio_node.heard
        leader = heard.get(self.leader_id) if self.leader_id is not None else None
        offset = georeference_offset_en_m(leader, self.scenario.home)
        max_age_s = report_max_age_s(self.scenario.control_rate_hz)
        ring = aggregate_polygon(heard, self.ring_order, offset, self.mission_t_s, max_age_s)
        truth_ring = self.flood.boundary_en_m(flood_t_s)
        if len(ring) >= 3:
            self.recorder.polygons.append(PolygonSample(t_s=flood_t_s, ring_en_m=ring))
            if self.polygon_log is not None:
                self.polygon_log.append(flood_t_s, ring)
            self.polygon_iou = polygon_iou(ring, truth_ring)
            try:
                feature = flood_polygon_from_enu(
                    ring, self.scenario.home, mission=self.mission, t_s=flood_t_s,
                    growth_rate_m2_per_s=polygon_growth_rate_m2ps(self.recorder.polygons),
                    vehicle_ids=[vid for vid in self.ring_order if vid in self.states and vid not in self.lost],
                    utc_iso=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
                )
                hub.put(self.keys.polygon, encode(feature))
                self.polygon_area_m2 = feature.properties.area_m2
            except ValueError:
                pass
        latest = self.recorder.latest()
        if latest is not None:
            positions, sides = latest
            water = np.asarray(self.flood.is_water(self._grid.centres_en_m(), flood_t_s), dtype=bool)
            self.coverage = footprint_coverage(self._grid, water, positions[:, :2], sides).coverage

    # ------------------------------------------------------------------ view and outputs
    def _snapshot(self, watcher: MavlinkWatcher, now_wall_s: float) -> MissionSnapshot:
        rows = []
        for vid in self.vehicle_ids:
            watch = watcher.vehicles.get(vid)
            state = self.states.get(vid)
            rows.append(VehicleRow(
                vehicle_id=vid, role=self.roles[vid], group=self.groups[vid],
                mode=watch.mode if watch else "-", armed=bool(watch and watch.armed),
                altitude_m=watch.altitude_m if watch else math.nan,
                heartbeat_age_s=watch.heartbeat_age_s(now_wall_s) if watch else math.inf,
                agent_alive=self.agent_alive.get(vid, False),
                state_age_s=self.mission_t_s - state.t_s if state else math.inf,
                battery_fraction=watch.battery_fraction if watch else math.nan,
                sees_edge=bool(state and state.has(FLAG_SEES_EDGE)),
            ))
        boundary = [vid for vid in self.vehicle_ids if self.roles[vid] == "boundary"]
        encircled = sum(1 for vid in boundary if vid in self.states and self.states[vid].encircle_complete)
        return MissionSnapshot(
            scenario=self.scenario.name, mode=self.options.mode, phase=self.phase, mission_t_s=self.mission_t_s,
            flood_t_s=None if self.flood_clock_start_s is None else self.flood_time_s(), duration_s=self.duration_s,
            speed=self.options.speed, vehicles=tuple(rows), encircled=encircled, boundary_count=len(boundary),
            encircle_time_s=self.recorder.encircle_time_s, polygon_iou=self.polygon_iou, coverage=self.coverage,
            polygon_area_m2=self.polygon_area_m2, events=tuple(self.events.recent), clock=self.options.clock,
            real_time_factor=self.pace_report.recent_real_time_factor if self.pace_report else math.nan,
        )

    def _report_exits(self) -> None:
        for child in self.supervisor.children:
            code = child.exit_code()
            if code not in (0, None, -signal.SIGTERM) and child.name not in {f"agent_{v}" for v in self._exited_agents}:
                self.events(f"{child.name} ended with code {code}")

    def _finish(self, code: int) -> int:
        """Write the outputs and the verdicts; returns the exit code (``--strict``: 1 on a degraded engine)."""
        engine = engine_verdict(self.pace_report, self.camera_stats, self.vehicle_ids, self.scenario.control_rate_hz,
                                self.options.clock, cameras_expected=any(r == "boundary" for r in self.roles.values()))
        self.events(engine.text())
        if code == EXIT_OK and self.options.strict and engine.health is EngineHealth.DEGRADED:
            code = EXIT_FAILED
        self.recorder.events = list(self.events.entries)
        if len(self.recorder):
            self.recorder.save_snapshot(self.out_dir / "record.npz")
        if len(self.recorder) < 2:
            self.console.print(f"no flight recorded ({engine.text()}); events and logs are in {self.out_dir}")
            return code
        try:
            write_mission_outputs(self.recorder.record(), self.flood, self.scenario.name, self.scenario.home,
                                  self.out_dir, self.scenario.camera.fov_deg, start_utc=self.flood_start_utc)
        except Exception as exc:  # noqa: BLE001 - the report must not hide the mission's own exit code
            self.console.print(f"[red]writing the report failed:[/] {exc}")
            print(f"gcs.processes: writing the report failed: {exc!r}", file=sys.stderr)
            return code
        self._print_summary(code, engine)
        return code

    def _print_summary(self, code: int, engine: EngineVerdict) -> None:
        metrics_path = self.out_dir / "metrics.json"
        if not metrics_path.exists():
            return
        try:
            metrics = json.loads(metrics_path.read_text())
        except (OSError, ValueError):
            return
        summary = metrics.get("summary", metrics)
        safety = safety_verdict(summary, self.failsafes)
        self.events(safety.text())
        metrics["engine_health"] = engine.as_json()
        metrics["safety"] = safety.as_json()
        write_metrics_json(metrics, metrics_path)
        keys = [k for k in ("encircle_time_s", "polygon_iou_final", "coverage_final", "spacing_cv_final",
                            "tracking_rms_last_10s_m", "min_pairwise_distance_m", "near_miss_pairs") if k in summary]
        shown = ", ".join(f"{k}={summary[k]:.3f}" if isinstance(summary[k], float) else f"{k}={summary[k]}" for k in keys)
        verdict = "complete" if code == EXIT_OK else "INCOMPLETE"
        self.console.print(f"metrics: {shown}; outputs in {self.out_dir}")
        for loss in metrics.get("losses", []):
            recovery = loss.get("recovery_time_s")
            recovered = f"spacing CV back under 0.1 after {recovery:.1f} s" if isinstance(recovery, float) else "no recovery"
            self.console.print(f"  vehicle {loss['vehicle_id']} ({loss['role']}) lost at flood time {loss['t_s']:.1f} s: "
                               f"{recovered}")
        self.console.print(f"mission {verdict} | {engine.text()} | {safety.text()}")


def _flood_box(flood, duration_s: float) -> tuple[np.ndarray, np.ndarray]:  # noqa: ANN001
    """A box holding the flood over the whole run, for the live coverage grid."""
    rings = [np.asarray(flood.boundary_en_m(t), dtype=float) for t in np.linspace(0.0, duration_s, 5)]
    points = np.concatenate(rings)
    return points.min(axis=0) - 2.0, points.max(axis=0) + 2.0
