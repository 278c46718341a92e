"""The process engine's options and the command lines of its children (pure).

The ground station resolves the scenario once and writes each child's slice as a plan file (``gcs.plan.files``);
the fleet, the camera renderer and every agent get ``--plan FILE`` and only what is about this run's machine (ports,
speed, the Zenoh endpoint). The radio emulator's few values travel on its command line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from comms.zenoh_session import DEFAULT_ENDPOINT, ZenohConfig
from gcs.polygon.radio_node import antenna_enu_m
from gcs.scenario import Scenario
from mission_plan.control_params import ControlMode
from mock_autopilot.ports import onboard_port
from vehicle_agents.flight_phase import PhaseLimits


@dataclass(frozen=True)
class ProcessOptions:
    """How to run a mission with the processes engine (ports configurable so tests never clash with a user's run)."""

    scenario_arg: str
    """The scenario name or TOML path, as given on the command line (for the record; children read plan files)."""
    overrides: tuple[str, ...] = ()
    mode: str = ControlMode.IMPROVED
    seed: int | None = None
    duration_s: float | None = None
    speed: float = 1.0
    out_dir: Path | None = None
    mission: str | None = None
    mavlink_base_port: int = 14540
    gcs_port: int = 14550
    zenoh_endpoint: str = DEFAULT_ENDPOINT
    live: bool = True
    startup_timeout_s: float = 60.0
    """Wall seconds start-up may go without progress (one more agent connected) before the run fails."""
    takeoff_timeout_s: float = 120.0
    """Mission seconds from start-up until every vehicle is airborne in OFFBOARD."""
    agent_link: str = "mavsdk"
    clock: str = "paced"
    """``paced``: the fleet holds each control tick for every live agent, the cameras and the radio; ``free``: not."""
    agent_timeout_s: float = 2.0
    """Paced clock: wall seconds a participant may hold a tick before the clock goes on without it."""
    strict: bool = False
    """A degraded engine (rates not held, agents left behind) fails the run (exit 1)."""
    extra_agent_args: tuple[str, ...] = field(default=())
    key_file: Path | None = None
    """The mission key to use (copied into the plan folder); None: a new one per mission."""
    dashboard_port: int | None = None
    """The live map's port (0: any free one; busy: a free one); None: no live map (``--no-dashboard``)."""
    dashboard_host: str = "127.0.0.1"
    dashboard_token: str | None = None
    """Operator commands from the live map need this token; without one the map is read-only."""
    dashboard_tiles: Path | None = None
    """A local MBTiles or PMTiles file served as the live map's base layer."""
    sim_faults: tuple[str, ...] = field(default=())
    start_agents: bool = True
    """False: the station starts no agent (they run on other hosts, the drones' companion computers)."""
    fleet_bind: str | None = None
    """The address the fleet's MAVLink sockets bind (None: loopback)."""
    onboard_partners: tuple[str, ...] = field(default=())
    """``IDS=IP``: where those vehicles' onboard links send (their companion computers), PX4's partner address."""
    """Fault injection in the fleet, ``KIND:INSTANCE[:VALUE]@T_S`` in fleet time (see ``python -m mock_autopilot``)."""


def hub_config(options: ProcessOptions) -> ZenohConfig:
    """The mission hub: a Zenoh peer the simulation's processes join (and mesh with), or, when the agents run on
    other hosts (``--no-agents``), a router: those hosts' routers reach the hub through its host's router, and a
    peer hub does not forward what the other peers on its host publish (the truth, the paced clock, the radio's
    bundles) to a router; a router hub does."""
    if options.start_agents:
        return ZenohConfig.hub(options.zenoh_endpoint)
    return ZenohConfig.router(listen=(options.zenoh_endpoint,))


def sim_command(options: ProcessOptions, plan: Path) -> list[str]:
    """The mock fleet with its simulator bridge (truth over Zenoh; the cameras run in their own process)."""
    return [
        "mock_autopilot.sim_bridge", "--plan", str(plan), "--speed", f"{options.speed:g}",
        "--base-port", str(options.mavlink_base_port), "--gcs-port", str(options.gcs_port),
        "--cameras", "none", "--connect", options.zenoh_endpoint, "--clock", options.clock,
        "--agent-timeout-s", f"{options.agent_timeout_s:g}",
        *[arg for fault in options.sim_faults for arg in ("--fault", fault)],
        *(["--bind", options.fleet_bind] if options.fleet_bind else []),
        *[arg for partner in options.onboard_partners for arg in ("--onboard-partner", partner)],
    ]


def cameras_command(options: ProcessOptions, plan: Path) -> list[str]:
    """The camera streams, in their own process, rendered from the truth the fleet publishes."""
    return ["mock_autopilot.sim_bridge.cameras", "--plan", str(plan), "--connect", options.zenoh_endpoint]


def radio_command(options: ProcessOptions, scenario: Scenario, mission: str, key_file: Path) -> list[str]:
    """The radio emulator, which relays only states signed with the mission key in ``key_file``."""
    radio = scenario.radio
    return [
        "comms.radio", "--mission", mission, "--range-m", f"{radio.range_m:g}", "--loss", f"{radio.loss:g}",
        "--latency-s", f"{radio.latency_s:g}", "--jitter-s", f"{radio.jitter_s:g}", "--seed", str(scenario.seed),
        "--burst-loss", f"{radio.burst_loss:g}", "--burst-mean-s", f"{radio.burst_mean_s:g}",
        "--burst-gap-s", f"{radio.burst_gap_s:g}", "--edge-loss", f"{radio.edge_loss:g}",
        "--edge-loss-exponent", f"{radio.edge_loss_exponent:g}",
        "--bandwidth-bytes-per-s", f"{radio.bandwidth_bytes_per_s:g}",
        *ground_node_args(scenario),
        "--speed", f"{options.speed:g}", "--connect", options.zenoh_endpoint, "--clock", options.clock,
        "--key-file", str(key_file),
    ]


def ground_node_args(scenario: Scenario) -> list[str]:
    """``--ground-node E N U`` when the ground station is a radio node (``radio.gcs_lossless = false``)."""
    if scenario.radio.gcs_lossless:
        return []
    antenna = antenna_enu_m(np.array([v.pad_enu_m for v in scenario.vehicles], dtype=float))
    return ["--ground-node", *(f"{c:.3f}" for c in antenna)]


MESH_LIMIT = 50
"""Up to this many agents every process is a Zenoh peer and the peers mesh (one direct link per pair: the
fewest hops). Beyond it the agents join as clients of the mission hub, which routes for them: a mesh of 200 agents
would be 20 000 links to open and keep alive on one machine."""


def agent_command(options: ProcessOptions, vehicle_id: int, plan: Path, fleet_size: int = 1) -> list[str]:
    """One drone's agent: its plan file and the onboard port of its mock PX4 (skipping the GCS port).

    A paced run given a longer agent timeout than the agents' own link timeout passes it on as their link timeout:
    a host that may hold an agent silent that long can hold its MAVSDK thread as long, and on two cores ``large``
    lost three agents to their 2 s wall-clock watchdog while their autopilots were streaming (docs/BENCHMARKS.md).
    The default agent timeout and the free clock keep the agents' own 2 s (SPEC §7: a lost autopilot noticed within
    3 s), as a real companion computer would."""
    port = onboard_port(options.mavlink_base_port, vehicle_id - 1, options.gcs_port)
    zenoh_mode = ["--zenoh-mode", "client"] if fleet_size > MESH_LIMIT else []
    link_timeout = (["--link-timeout", f"{options.agent_timeout_s:g}"]
                    if options.clock == "paced" and options.agent_timeout_s > PhaseLimits.link_timeout_s else [])
    return [
        "vehicle_agents", "--plan", str(plan), "--mavlink", f"udpin://0.0.0.0:{port}", "--link", options.agent_link,
        "--speed", f"{options.speed:g}", "--clock", options.clock, "--connect", options.zenoh_endpoint,
        *zenoh_mode, *link_timeout, *options.extra_agent_args,
    ]
