"""``python -m vehicle_agents --id N --role boundary --mavlink udpin://0.0.0.0:14540+i --scenario circle``.

One drone's onboard computer. Reads its mission plan (role, group, pad, control parameters) from the scenario,
connects to its autopilot over MAVLink (MAVSDK by default), joins the swarm over Zenoh, and flies until told to
stop, until it lands, or until its autopilot falls silent. Exit codes: 0 done, 2 bad arguments or scenario,
3 vehicle lost, 4 could not start (no autopilot, Zenoh unreachable).
"""

from __future__ import annotations

import argparse
import asyncio
import logging
import signal
import sys
from collections.abc import Sequence

from comms.keys import KeyNameError, validate_mission
from comms.cli_args import add_zenoh_arguments, zenoh_config_from_args
from comms.zenoh_session import ZenohOpenError
from gcs.scenario import ScenarioError, load_scenario
from vehicle_agents.agent import EXIT_START_FAILED, Agent, AgentConfig
from vehicle_agents.flight_phase import PhaseLimits

EXIT_USAGE = 2


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m vehicle_agents", description="One FloodWatch drone's onboard agent.")
    p.add_argument("--id", type=int, required=True, dest="vehicle_id", help="vehicle id (= MAVLink system id)")
    p.add_argument("--role", choices=("boundary", "leader", "follower"), help="must match the scenario's plan")
    p.add_argument("--mavlink", help="autopilot URL (default udpin://0.0.0.0:<14540 + id - 1>)")
    p.add_argument("--mavlink-base-port", type=int, default=14540, help="base of the default URL's port")
    p.add_argument("--link", choices=("mavsdk", "pymavlink"), default="mavsdk", help="MAVLink library")
    p.add_argument("--scenario", default="circle", help="bundled scenario name or TOML path")
    p.add_argument("--set", action="append", default=[], dest="overrides", metavar="KEY=VALUE")
    p.add_argument("--mode", choices=("paper", "improved"), default="improved")
    p.add_argument("--mission", help="mission name in the Zenoh keys (default: the scenario name)")
    p.add_argument("--neighbours", choices=("radio", "direct"), default="radio",
                   help="hear neighbours through the radio emulator (simulation) or directly (real radio)")
    p.add_argument("--speed", type=float, default=1.0, help="simulation speed factor (mission s per wall s)")
    p.add_argument("--rate-hz", type=float, help="control rate in mission time (default: the scenario's)")
    p.add_argument("--connect-timeout", type=float, default=30.0, help="wall seconds to wait for the autopilot")
    p.add_argument("--link-timeout", type=float, default=2.0, help="wall seconds of autopilot silence = vehicle lost")
    p.add_argument("--log-level", default="INFO")
    add_zenoh_arguments(p)
    return p


def _config(args: argparse.Namespace) -> tuple[AgentConfig, str, str]:
    scenario = load_scenario(args.scenario, args.overrides)
    spec = next((v for v in scenario.vehicles if v.vehicle_id == args.vehicle_id), None)
    if spec is None:
        raise ScenarioError(f"--id {args.vehicle_id}: scenario {scenario.name} has vehicles 1..{len(scenario.vehicles)}")
    if args.role is not None and args.role != spec.role:
        raise ScenarioError(f"--role {args.role}: scenario {scenario.name} plans vehicle {spec.vehicle_id} as {spec.role}")
    if not args.speed > 0:
        raise ScenarioError(f"--speed {args.speed}: must be > 0")
    rate_hz = args.rate_hz if args.rate_hz is not None else scenario.control_rate_hz
    if not rate_hz > 0:
        raise ScenarioError(f"--rate-hz {rate_hz}: must be > 0")
    mission = validate_mission(args.mission or scenario.name)
    url = args.mavlink or f"udpin://0.0.0.0:{args.mavlink_base_port + args.vehicle_id - 1}"
    config = AgentConfig(
        vehicle_id=spec.vehicle_id,
        role=spec.role,
        group=spec.group,
        pad_enu_m=(spec.pad_enu_m[0], spec.pad_enu_m[1]),
        has_gps=spec.has_gps,
        params=scenario.control_params(args.mode),
        control_rate_hz=rate_hz,
        speed=args.speed,
        connect_timeout_s=args.connect_timeout,
        limits=PhaseLimits(takeoff_altitude_m=scenario.altitude_m, link_timeout_s=args.link_timeout),
    )
    return config, mission, url


def _make_link(kind: str, url: str):  # noqa: ANN202 - returns an AutopilotLink
    if kind == "pymavlink":
        from vehicle_agents.autopilot_link_pymavlink import PymavlinkAutopilotLink

        return PymavlinkAutopilotLink(url)
    from vehicle_agents.autopilot_link_mavsdk import MavsdkAutopilotLink

    return MavsdkAutopilotLink(url)


async def _run(agent: Agent) -> int:
    loop = asyncio.get_running_loop()
    for sig in (signal.SIGTERM, signal.SIGINT):
        loop.add_signal_handler(sig, agent.request_stop)
    return await agent.run()


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(name)s %(levelname)s %(message)s")
    try:
        config, mission, url = _config(args)
        zenoh = zenoh_config_from_args(args)
    except (ScenarioError, KeyNameError, ValueError) as exc:
        print(f"vehicle_agents: {exc}", file=sys.stderr)
        return EXIT_USAGE
    from vehicle_agents.swarm_link_zenoh import ZenohSwarmLink

    try:
        swarm = ZenohSwarmLink(config.vehicle_id, mission, zenoh, via_radio=args.neighbours == "radio",
                               period_s=1.0 / config.control_rate_hz)
    except ZenohOpenError as exc:
        print(f"vehicle_agents: vehicle {config.vehicle_id}: {exc}", file=sys.stderr)
        return EXIT_START_FAILED
    agent = Agent(config, _make_link(args.link, url), swarm)
    code = asyncio.run(_run(agent))
    stats = agent.stats
    logging.getLogger("vehicle_agents").info(
        "vehicle %d exits with %d: %d control steps (%.1f Hz mission time), %d overruns, %d frames processed, "
        "%d frames missed", config.vehicle_id, code, stats.control_steps, stats.control_rate_hz(config.speed),
        stats.overruns, stats.frames_processed, stats.frames_dropped)
    return code


if __name__ == "__main__":
    sys.exit(main())
