"""Argument parsing and dispatch for ``python -m gcs.mission`` (thin: every decision lives in the engines).

Bad input (unknown scenario, bad ``--set``, out-of-range value) prints ONE line on stderr and exits with 2.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys
from collections.abc import Sequence
from datetime import datetime, timezone
from pathlib import Path

from comms.key_file import KeyFileError, read_key_file
from gcs.dashboard.cli_checks import check_dashboard_args
from gcs.mission.options import BACKENDS, CLOCKS, ENGINES, MissionOptions
from gcs.one_line_argparse import EXIT_USAGE, OneLineArgumentParser
from gcs.scenario import Scenario, ScenarioError, load_scenario
from mission_plan.control_params import ControlMode
from mock_autopilot.ports import link_hosts
from mock_autopilot.world.hydro_cache import CACHE_ENV
from vehicle_agents.control.params import MODES


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineArgumentParser(prog="python -m gcs.mission", description="Run a FloodWatch mission (SPEC §4-§6).",
                                   label="gcs.mission")
    parser.add_argument("scenario", help="bundled scenario name (circle, ellipse, ...) or path to a .toml file")
    parser.add_argument("--engine", choices=ENGINES, default="processes", help="default: processes")
    parser.add_argument("--backend", choices=BACKENDS, default=None,
                        help="lockstep vehicle dynamics: kinematic (default) or px4, the mock PX4 itself (modes, "
                             "failsafes); the processes engine always flies the mock PX4 fleet")
    parser.add_argument("--mode", choices=MODES, default=ControlMode.IMPROVED.value,
                        help="control laws: improved (default) or paper, the laws as printed (docs/RESULTS.md)")
    parser.add_argument("--seed", type=int, default=None, help="seed for the flood, camera noise and radio")
    parser.add_argument("--duration", type=float, default=None, metavar="S", help="simulated seconds (default: scenario)")
    parser.add_argument("--speed", type=float, default=1.0, metavar="S",
                        help="simulation speed-up (processes engine; with the paced clock the most it runs at)")
    parser.add_argument("--clock", choices=CLOCKS, default=None,
                        help="processes engine: paced (default) holds each control tick until every live agent, the "
                             "cameras and the radio have done theirs, so a slow host gives a slower run, never a "
                             "different one; free runs at --speed whatever they do (real-time faults)")
    parser.add_argument("--agent-timeout-s", type=float, default=2.0, metavar="S",
                        help="paced clock: wall seconds an agent may hold a tick before it is left behind (default 2); "
                             "longer also becomes the agents' own autopilot-silence timeout")
    parser.add_argument("--startup-timeout-s", type=float, default=60.0, metavar="S",
                        help="processes engine: wall seconds start-up may go without one more agent connecting "
                             "before the run fails as stalled (default 60; a slow start that progresses goes on)")
    parser.add_argument("--strict", action="store_true",
                        help="exit 1 when the engine was degraded (agents or cameras below their rate, agents left "
                             "behind), not only when the mission failed")
    parser.add_argument("--out", type=Path, default=None, metavar="DIR",
                        help="output folder (default runs/<timestamp>-<scenario>-<engine>-<mode>)")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                        help="override a scenario parameter, e.g. --set flood.radius_end_m=20 (repeatable)")
    parser.add_argument("--base-port", type=int, default=14540, help="first vehicle's MAVLink API port (processes)")
    parser.add_argument("--gcs-port", type=int, default=14550, help="ground station MAVLink port (processes)")
    hosts = parser.add_argument_group("agents on other hosts (processes engine)")
    hosts.add_argument("--no-agents", dest="start_agents", action="store_false",
                       help="start no agent: they run on the drones' companion computers and join over Zenoh")
    hosts.add_argument("--fleet-bind", default=None, metavar="ADDR",
                       help="address the mock fleet's MAVLink sockets bind (default 127.0.0.1; 0.0.0.0: every one)")
    hosts.add_argument("--onboard-partner", action="append", default=[], metavar="IDS=IP",
                       help="these vehicles' onboard links go to their companion computer at IP, e.g. 1-4=10.0.0.2")
    parser.add_argument("--cache-dir", type=Path, default=None, metavar="DIR",
                        help="where hydrodynamic flood runs are cached (default: the user's cache directory); "
                             "every process started inherits it")
    parser.add_argument("--no-live", dest="live", action="store_false", help="no live terminal view")
    parser.add_argument("--key-file", type=Path, default=None, metavar="FILE",
                        help="mission key that signs commands and states (default: a new one in <out>/plan/mission.key)")
    map_args = parser.add_argument_group("live map in a browser (processes engine)")
    map_args.add_argument("--dashboard-port", type=int, default=8080, metavar="N",
                          help="port of the live map (default 8080; when busy a free one, printed; 0: any free one)")
    map_args.add_argument("--no-dashboard", dest="dashboard", action="store_false", help="no live map")
    map_args.add_argument("--dashboard-host", default="127.0.0.1", metavar="ADDR",
                          help="address the live map listens on (default 127.0.0.1; any other prints a warning)")
    map_args.add_argument("--dashboard-token", default=None, metavar="TOKEN",
                          help="operator token: with it the map's hold / resume / land-all work for whoever sends it; "
                               "without it the map is read-only")
    map_args.add_argument("--tiles", type=Path, default=None, metavar="FILE",
                          help="local raster MBTiles or PMTiles file as the live map's base layer (no online tiles)")
    return parser


def default_out_dir(scenario: str, engine: str, mode: str, now: datetime | None = None) -> Path:
    """``runs/<UTC timestamp>-<scenario>-<engine>-<mode>``."""
    stamp = (now or datetime.now(timezone.utc)).strftime("%Y%m%dT%H%M%SZ")
    name = Path(scenario).stem if scenario.endswith(".toml") else scenario
    return Path("runs") / f"{stamp}-{name}-{engine}-{mode}"


def parse_options(argv: Sequence[str]) -> MissionOptions:
    """Parse and check the flags (exit 2 with one line on bad values)."""
    ns = build_parser().parse_args(list(argv))
    if ns.duration is not None and not ns.duration > 0.0:
        _fail(f"--duration: must be > 0, got {ns.duration:g}")
    if not ns.speed > 0.0:
        _fail(f"--speed: must be > 0, got {ns.speed:g}")
    if ns.seed is not None and ns.seed < 0:
        _fail(f"--seed: must be >= 0, got {ns.seed}")
    for name in ("base_port", "gcs_port"):
        if not 1 <= getattr(ns, name) <= 65535:
            _fail(f"--{name.replace('_', '-')}: must be a port number, got {getattr(ns, name)}")
    if not ns.agent_timeout_s > 0.0:
        _fail(f"--agent-timeout-s: must be > 0, got {ns.agent_timeout_s:g}")
    if not 0.0 < ns.startup_timeout_s < math.inf:
        _fail(f"--startup-timeout-s: must be a finite number of seconds > 0, got {ns.startup_timeout_s:g}")
    if ns.clock is not None and ns.engine != "processes":
        _fail(f"--clock {ns.clock}: only the processes engine has a clock to choose (lockstep is one loop)")
    if ns.backend is not None and ns.engine != "lockstep":
        _fail(f"--backend {ns.backend}: only the lockstep engine has a choice (processes fly the mock PX4 fleet)")
    if ns.key_file is not None:
        try:
            read_key_file(ns.key_file)
        except KeyFileError as exc:
            _fail(f"--key-file: {exc}")
    check_dashboard_args(ns.dashboard_port, ns.dashboard_token, ns.tiles, _fail)
    if ns.engine != "processes" and (not ns.start_agents or ns.fleet_bind or ns.onboard_partner):
        _fail("--no-agents, --fleet-bind, --onboard-partner: only the processes engine has agents and a fleet to place")
    try:
        link_hosts(ns.fleet_bind, ns.onboard_partner)
    except ValueError as exc:
        _fail(str(exc).replace("--bind", "--fleet-bind"))
    out = ns.out if ns.out is not None else default_out_dir(ns.scenario, ns.engine, ns.mode)
    if ns.cache_dir is not None:
        os.environ[CACHE_ENV] = str(ns.cache_dir.resolve())
    return MissionOptions(
        scenario=ns.scenario, engine=ns.engine, mode=ns.mode, seed=ns.seed, duration_s=ns.duration, speed=ns.speed,
        out_dir=out, overrides=tuple(ns.overrides), base_port=ns.base_port, gcs_port=ns.gcs_port, live=ns.live,
        backend=ns.backend or "kinematic", clock=ns.clock or "paced", agent_timeout_s=ns.agent_timeout_s,
        startup_timeout_s=ns.startup_timeout_s, strict=ns.strict, key_file=ns.key_file,
        dashboard_port=ns.dashboard_port if ns.dashboard else None, dashboard_host=ns.dashboard_host,
        dashboard_token=ns.dashboard_token, dashboard_tiles=ns.tiles,
        start_agents=ns.start_agents, fleet_bind=ns.fleet_bind, onboard_partners=tuple(ns.onboard_partner),
    )


def resolve_scenario(options: MissionOptions) -> Scenario:
    """Load the scenario with ``--set`` overrides and ``--seed``, then ``--duration``; raises ScenarioError.

    The seed goes in as one more override, before resolution: what it draws ("auto" launch pads on a seeded
    terrain) then agrees with the run's seed.
    """
    seed = [f"seed={options.seed}"] if options.seed is not None else []
    scenario = load_scenario(options.scenario, [*options.overrides, *seed])
    if options.duration_s is not None:
        return dataclasses.replace(scenario, duration_s=options.duration_s)
    return scenario


def _fail(message: str) -> None:
    print(f"gcs.mission: {message}", file=sys.stderr)
    raise SystemExit(EXIT_USAGE)


def main(argv: Sequence[str] | None = None) -> int:
    """Parse, load the scenario, dispatch to the engine; returns the process exit code."""
    options = parse_options(sys.argv[1:] if argv is None else argv)
    try:
        scenario = resolve_scenario(options)
        if options.engine == "lockstep":
            from gcs.lockstep.run import run_mission as run_lockstep_mission

            return run_lockstep_mission(scenario, options)
        from gcs.processes import run_mission

        return run_mission(scenario, options)
    except ScenarioError as exc:
        print(f"gcs.mission: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("gcs.mission: interrupted", file=sys.stderr)
        return 130
