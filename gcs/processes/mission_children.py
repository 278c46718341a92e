"""The simulation's child processes of a mission: the fleet with its simulator bridge, the cameras, the radio, and
one agent per vehicle, started a few at a time.

Agents start four per core of the machine still connecting: 200 interpreters importing at once would starve the
ones already up past their link watchdogs. On real drones none of these exist (the agents run on the drones), and
the ground station starts none of them.
"""

from __future__ import annotations

import json
import os
import signal
import time
from collections.abc import Callable, Container, Mapping
from pathlib import Path

from comms.key_file import KeyFileError, read_key_file
from comms.signing import MissionKey
from gcs.plan.files import write_plans
from gcs.processes.host_capacity import agent_niceness
from gcs.processes.launch import ProcessOptions, agent_command, cameras_command, radio_command, sim_command
from gcs.processes.supervisor import Child, Supervisor
from gcs.scenario import Scenario


class ChildFailed(RuntimeError):
    """A child the mission cannot do without exited; the message is the one line the user sees."""


class StartupProgress:
    """When start-up last moved on: the start, or the newest agent that connected. Start-up fails when it stalls
    for ``startup_timeout_s``, not when it is merely slow (208 agents on 2 busy cores came up at one per 3 s, ten
    minutes in all)."""

    def __init__(self) -> None:
        self.connected = 0
        self._progress_wall_s = 0.0

    def last_progress_wall_s(self, started_wall_s: float, connected: int) -> float:
        if connected != self.connected:
            self.connected = connected
            self._progress_wall_s = time.monotonic()
        return max(started_wall_s, self._progress_wall_s)


class MissionChildren:
    """Starts, watches and stops the mission's processes (every one is stopped by :meth:`stop_all`)."""

    def __init__(self, scenario: Scenario, options: ProcessOptions, out_dir: Path, mission: str,
                 events: Callable[[str], None]) -> None:
        self.scenario, self.options, self.out_dir, self.mission = scenario, options, out_dir, mission
        self.events = events
        self.supervisor = Supervisor(out_dir)
        self.services: dict[str, Child] = {}
        self.agents: dict[int, Child] = {}
        self.to_start: list[int] = []
        self.exited_agents: set[int] = set()
        self._plans: Mapping[int, Path] = {}
        self.key_path: Path | None = None
        self.mission_key: MissionKey | None = None
        self._fleet_size = len(scenario.vehicles)
        self._agent_niceness: dict[int, int] = {}

    @staticmethod
    def max_connecting() -> int:
        return 4 * len(os.sched_getaffinity(0))

    def start(self, connected: Container[int]) -> None:
        """Write every plan file and the mission key (``--key-file`` or a new one), start the fleet+truth, cameras
        and radio, then the first agents."""
        opts = self.options
        try:
            plans = write_plans(self.scenario, opts.mode, (self.out_dir / "plan").resolve(), self.mission, opts.key_file)
            self.mission_key = read_key_file(plans.key)
        except KeyFileError as exc:
            raise ChildFailed(str(exc)) from None
        self.key_path = plans.key
        self.services["sim"] = self.supervisor.start("sim", sim_command(opts, plans.fleet))
        self.services["cameras"] = self.supervisor.start("cameras", cameras_command(opts, plans.cameras))
        self.services["radio"] = self.supervisor.start("radio", radio_command(opts, self.scenario, self.mission, plans.key))
        self._plans = plans.agents
        self.to_start = [v.vehicle_id for v in self.scenario.vehicles] if opts.start_agents else []
        self._write_pids()
        if opts.start_agents:
            self.events(f"started the fleet+truth, cameras and radio processes; {len(self.to_start)} agents "
                        f"follow, {self.max_connecting()} at a time (logs in {self.out_dir})")
        else:
            self.events(f"started the fleet+truth, cameras and radio processes; the agents run elsewhere (their plans "
                        f"in {plans.fleet.parent}) and join over Zenoh")
        self.start_agents(connected)

    def start_agents(self, connected: Container[int]) -> list[int]:
        """Start the next agents while fewer than :meth:`max_connecting` are still connecting (not in
        ``connected``); returns the ids started.

        Each agent's nice follows the agents started so far, not the whole fleet (``agent_niceness``: all of them
        together weigh about four simulator processes): the first agents of a 208-vehicle fleet at the nice the
        whole fleet gets (18) would weigh 8 x 18 / 1024 of one process against a busy host and not even finish
        their imports. As more start, those already running are lowered to the same nice."""
        connecting = sum(1 for vid in self.agents if vid not in connected)
        started: list[int] = []
        while self.to_start and connecting < self.max_connecting():
            vid = self.to_start.pop(0)
            niceness = agent_niceness(len(self.agents) + 1)
            self.agents[vid] = self.supervisor.start(
                f"agent_{vid}", agent_command(self.options, vid, self._plans[vid], self._fleet_size),
                niceness=niceness,
            )
            self._agent_niceness[vid] = niceness
            connecting += 1
            started.append(vid)
        if started:
            self._lower_earlier_agents(agent_niceness(len(self.agents)))
            self._write_pids()
            if not self.to_start:
                self.events(f"all {len(self.agents)} agents started")
        return started

    def _lower_earlier_agents(self, niceness: int) -> None:
        """Give every running agent started at a higher priority the nice of the fleet started so far."""
        for vid, child in self.agents.items():
            if self._agent_niceness.get(vid, niceness) < niceness and child.exit_code() is None:
                if self.supervisor.lower_priority(child, niceness):
                    self._agent_niceness[vid] = niceness

    @property
    def expected_agents(self) -> list[int]:
        """The agents the mission waits for: those this station started, or every vehicle's when they run elsewhere."""
        return list(self.agents) if self.options.start_agents else [v.vehicle_id for v in self.scenario.vehicles]

    def newly_exited_agents(self) -> list[tuple[int, int, Child]]:
        """(vehicle id, exit code, child) of agents that exited since the last call; raises :class:`ChildFailed`
        when a service (fleet, cameras, radio) exited."""
        for name, child in self.services.items():
            code = child.exit_code()
            if code is not None:
                raise ChildFailed(f"{name} process exited with code {code}: {child.log_tail()}")
        exited = []
        for vid, child in self.agents.items():
            code = child.exit_code()
            if code is None or vid in self.exited_agents:
                continue
            self.exited_agents.add(vid)
            exited.append((vid, code, child))
        return exited

    def stop_all(self) -> None:
        """Stop every child and report the unexpected exit codes."""
        self.supervisor.stop_all()
        agents_seen = {f"agent_{v}" for v in self.exited_agents}
        for child in self.supervisor.children:
            code = child.exit_code()
            if code not in (0, None, -signal.SIGTERM) and child.name not in agents_seen:
                self.events(f"{child.name} ended with code {code}")

    def _write_pids(self) -> None:
        pids = {child.name: child.pid for child in self.supervisor.children}
        (self.out_dir / "processes.json").write_text(json.dumps(pids, indent=1))
