"""The processes engine: the mission as users run it, one OS process per part (SPEC §1).

``python -m gcs.mission circle`` (engine ``processes``, the default) calls :func:`run_mission`, which starts the mock
PX4 fleet with its simulator bridge, the radio emulator and one agent process per vehicle, and runs the ground
station (:mod:`gcs.processes.ground_station`) until the flood clock reaches the mission's duration.
"""

from __future__ import annotations

import asyncio
import datetime as dt
import os
import sys
from pathlib import Path
from typing import Any

from gcs.processes.launch import ProcessOptions
from gcs.scenario import Scenario

__all__ = ["ProcessOptions", "run_mission", "run_processes", "process_options"]

EXIT_USAGE = 2
ZENOH_ENDPOINT_ENV = "FLOODWATCH_ZENOH_ENDPOINT"
"""Where the mission's Zenoh hub listens when the mission CLI runs us (default tcp/127.0.0.1:7447); tests set it so
they never clash with a user's running mission."""


def default_out_dir(scenario_name: str) -> Path:
    """``runs/<UTC timestamp>-<scenario>-processes`` under the current directory."""
    stamp = dt.datetime.now(dt.timezone.utc).strftime("%Y%m%dT%H%M%SZ")
    return Path("runs") / f"{stamp}-{scenario_name}-processes"


def process_options(scenario: Scenario, options: Any) -> ProcessOptions:
    """Our options from the mission CLI's ``MissionOptions`` (fields it lacks keep their defaults)."""
    if isinstance(options, ProcessOptions):
        return options
    fields = ProcessOptions.__dataclass_fields__
    values: dict[str, Any] = {}
    aliases = {"scenario_arg": ("scenario_arg", "scenario", "scenario_name"), "overrides": ("overrides", "sets"),
               "out_dir": ("out_dir", "out"), "mavlink_base_port": ("mavlink_base_port", "base_port"),
               "zenoh_endpoint": ("zenoh_endpoint", "zenoh")}
    for name in fields:
        for alias in aliases.get(name, (name,)):
            value = getattr(options, alias, None)
            if value is not None:
                values[name] = value
                break
    values.setdefault("scenario_arg", scenario.name)
    env_endpoint = os.environ.get(ZENOH_ENDPOINT_ENV)
    if env_endpoint and "zenoh_endpoint" not in values:
        values["zenoh_endpoint"] = env_endpoint
    values["overrides"] = tuple(values.get("overrides", ()))
    if values.get("out_dir") is not None:
        values["out_dir"] = Path(values["out_dir"])
    return ProcessOptions(**values)


def run_processes(scenario: Scenario, options: ProcessOptions) -> int:
    """Run one mission with the processes engine; returns the exit code (0 only when it ran to the end)."""
    from gcs.processes.ground_station import GroundStation

    from mock_autopilot.world.config import FloodConfigError, flood_model_from_config
    from vehicle_agents.control.params import ControlParamsError

    try:
        flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
        scenario.control_params(options.mode)
        if not options.speed > 0:
            raise ValueError(f"--speed: must be > 0, got {options.speed:g}")
    except (FloodConfigError, ControlParamsError, ValueError) as exc:
        print(f"gcs.mission: {exc}", file=sys.stderr)
        return EXIT_USAGE
    out_dir = options.out_dir or default_out_dir(scenario.name)
    out_dir.mkdir(parents=True, exist_ok=True)
    station = GroundStation(scenario, options, out_dir)
    return asyncio.run(station.run())


def run_mission(scenario: Scenario, options: Any) -> int:
    """Entry point the mission CLI dispatches to for ``--engine processes``."""
    return run_processes(scenario, process_options(scenario, options))
