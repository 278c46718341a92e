"""The process engine's options and the command lines of its children (pure).

Children load the same scenario file with the same ``--set`` overrides as the ground station, so every process
agrees on the plan without a side channel; the seed travels as one more override.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from comms.zenoh_session import DEFAULT_ENDPOINT
from gcs.scenario import Scenario
from mock_autopilot.ports import onboard_port


@dataclass(frozen=True)
class ProcessOptions:
    """How to run a mission with the processes engine (ports configurable so tests never clash with a user's run)."""

    scenario_arg: str
    """The scenario name or TOML path, as given on the command line (children load it again)."""
    overrides: tuple[str, ...] = ()
    mode: str = "improved"
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
    """Wall seconds for every child to come up (vehicles heard on the GCS link, agents' liveliness tokens)."""
    takeoff_timeout_s: float = 120.0
    """Mission seconds from start-up until every vehicle is airborne in OFFBOARD."""
    agent_link: str = "mavsdk"
    extra_agent_args: tuple[str, ...] = field(default=())
    sim_faults: tuple[str, ...] = field(default=())
    """Fault injection in the fleet, ``KIND:INSTANCE[:VALUE]@T_S`` in fleet time (see ``python -m mock_autopilot``)."""


def effective_overrides(options: ProcessOptions) -> list[str]:
    sets = list(options.overrides)
    if options.seed is not None:
        sets.append(f"seed={options.seed}")
    return sets


def _set_args(options: ProcessOptions) -> list[str]:
    args: list[str] = []
    for assignment in effective_overrides(options):
        args += ["--set", assignment]
    return args


def sim_command(options: ProcessOptions, mission: str) -> list[str]:
    """The mock fleet with its simulator bridge (camera frames and truth over Zenoh)."""
    return [
        "mock_autopilot.sim_bridge", "--scenario", options.scenario_arg, *_set_args(options),
        "--mission", mission, "--speed", f"{options.speed:g}",
        "--base-port", str(options.mavlink_base_port), "--gcs-port", str(options.gcs_port),
        "--cameras", "none", "--connect", options.zenoh_endpoint,
        *[arg for fault in options.sim_faults for arg in ("--fault", fault)],
    ]


def cameras_command(options: ProcessOptions, mission: str) -> list[str]:
    """The camera streams, in their own process, rendered from the truth the fleet publishes."""
    return [
        "mock_autopilot.sim_bridge.cameras", "--scenario", options.scenario_arg, *_set_args(options),
        "--mission", mission, "--connect", options.zenoh_endpoint,
    ]


def radio_command(options: ProcessOptions, scenario: Scenario, mission: str) -> list[str]:
    radio = scenario.radio
    return [
        "comms.radio", "--mission", mission, "--range-m", f"{radio.range_m:g}", "--loss", f"{radio.loss:g}",
        "--latency-s", f"{radio.latency_s:g}", "--jitter-s", f"{radio.jitter_s:g}", "--seed", str(scenario.seed),
        "--speed", f"{options.speed:g}", "--connect", options.zenoh_endpoint,
    ]


def agent_command(options: ProcessOptions, vehicle_id: int, role: str, mission: str) -> list[str]:
    port = onboard_port(options.mavlink_base_port, vehicle_id - 1, options.gcs_port)
    return [
        "vehicle_agents", "--id", str(vehicle_id), "--role", role, "--mavlink", f"udpin://0.0.0.0:{port}",
        "--link", options.agent_link, "--scenario", options.scenario_arg, *_set_args(options),
        "--mode", options.mode, "--mission", mission, "--speed", f"{options.speed:g}",
        "--connect", options.zenoh_endpoint, *options.extra_agent_args,
    ]
