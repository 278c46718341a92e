"""``python -m vehicle_agents --plan agent_3.json`` (or ``--id 3 --scenario circle``): one drone's onboard computer.

Its mission plan (who it is, its pad, the control parameters with the roster, rates, altitude) comes from a plan
file, what a real drone's companion computer receives like any mission file: the ground station writes one per
drone (``<run>/plan/agent_<id>.json``) and ``python -m gcs.plan SCENARIO --out DIR`` writes them for deployment.
``--scenario NAME`` (with ``--id``, ``--set``, ``--mode``) resolves a scenario locally through ``mission_plan`` as
a convenience; a scenario whose pads are "auto" needs the flood model and therefore a plan file. Nothing here
imports the ground station or builds the flood model.

The agent connects to its autopilot over MAVLink (MAVSDK by default), joins the swarm over Zenoh, and flies until
told to stop, until it lands, or until its autopilot falls silent. Exit codes: 0 done, 2 bad arguments, scenario or
plan, 3 vehicle lost, 4 could not start (no autopilot, Zenoh unreachable).
"""

from __future__ import annotations

import argparse
import asyncio
import logging
import signal
import sys
from collections.abc import Sequence
from pathlib import Path

import cv2

from comms.key_file import KEY_FILE_NAME, KeyFileError, read_key_file
from comms.keys import KeyNameError, validate_mission
from comms.signing import MissionKey
from comms.cli_args import add_zenoh_arguments, zenoh_config_from_args
from comms.zenoh_session import ZenohOpenError
from mission_plan.control_params import MODES, ControlMode
from mission_plan.plan_files import PlanFileError, read_plan
from mission_plan.plans import AgentPlan, agent_plan
from mission_plan.roles import Role
from mission_plan.scenario_files import load_scenario
from mission_plan.table_fields import ScenarioError
from vehicle_agents.agent import EXIT_START_FAILED, Agent, AgentConfig
from vehicle_agents.flight_phase import PhaseLimits

EXIT_USAGE = 2


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m vehicle_agents", description="One FloodWatch drone's onboard agent.")
    p.add_argument("--plan", type=Path, metavar="FILE", help="this drone's plan file (agent plan JSON)")
    p.add_argument("--id", type=int, dest="vehicle_id", help="vehicle id (= MAVLink system id); with --scenario")
    p.add_argument("--role", choices=[r.value for r in Role], help="must match the plan")
    p.add_argument("--mavlink", help="autopilot URL (default udpin://0.0.0.0:<14540 + id - 1>)")
    p.add_argument("--mavlink-base-port", type=int, default=14540, help="base of the default URL's port")
    p.add_argument("--link", choices=("mavsdk", "pymavlink"), default="mavsdk", help="MAVLink library")
    p.add_argument("--scenario", help="without --plan: bundled scenario name or TOML path (default circle)")
    p.add_argument("--set", action="append", default=[], dest="overrides", metavar="KEY=VALUE",
                   help="with --scenario: override a scenario parameter")
    p.add_argument("--mode", choices=MODES, help="with --scenario: control laws (default improved); with --plan: "
                                                  "must match the plan's")
    p.add_argument("--mission", help="mission name in the Zenoh keys (default: the plan's)")
    p.add_argument("--neighbours", choices=("radio", "direct"), default="radio",
                   help="hear neighbours through the radio emulator (simulation) or directly (real radio)")
    p.add_argument("--speed", type=float, default=1.0, help="simulation speed factor (mission s per wall s)")
    p.add_argument("--clock", choices=("free", "paced"), default="free",
                   help="free: keep time on the wall clock (a real drone); paced: compute one tick per simulator "
                        "clock tick and acknowledge it (a simulation run with --clock paced)")
    p.add_argument("--rate-hz", type=float, help="control rate in mission time (default: the plan's)")
    p.add_argument("--connect-timeout", type=float, default=30.0, help="wall seconds to wait for the autopilot")
    p.add_argument("--link-timeout", type=float, default=2.0, help="wall seconds of autopilot silence = vehicle lost")
    p.add_argument("--key-file", type=Path, metavar="FILE",
                   help=f"the mission key (default: {KEY_FILE_NAME} beside the --plan file)")
    p.add_argument("--log-level", default="INFO")
    add_zenoh_arguments(p)
    return p


def load_agent_plan(args: argparse.Namespace) -> AgentPlan:
    """This drone's plan: the ``--plan`` file, or the ``--scenario`` resolved locally (no flood model)."""
    if args.plan is not None:
        if args.scenario is not None or args.overrides:
            raise ScenarioError("--plan: the plan is already resolved; --scenario and --set apply without it")
        plan = read_plan(args.plan, AgentPlan)
        if args.vehicle_id is not None and args.vehicle_id != plan.vehicle.vehicle_id:
            raise ScenarioError(f"--id {args.vehicle_id}: the plan {args.plan} is vehicle {plan.vehicle.vehicle_id}'s")
        if args.mode is not None and args.mode != plan.params.mode:
            raise ScenarioError(f"--mode {args.mode}: the plan {args.plan} was made for mode {plan.params.mode}")
        return plan
    if args.vehicle_id is None:
        raise ScenarioError("--id: required with --scenario (or give a --plan file)")
    scenario = load_scenario(args.scenario or "circle", args.overrides)
    return agent_plan(scenario, args.vehicle_id, args.mode or ControlMode.IMPROVED)


def agent_config(plan: AgentPlan, *, rate_hz: float | None = None, speed: float = 1.0, paced: bool = False,
                 connect_timeout_s: float = 30.0, link_timeout_s: float = 2.0) -> AgentConfig:
    """The agent's configuration from its plan; ``rate_hz`` overrides the plan's control rate."""
    vehicle = plan.vehicle
    control_rate_hz = plan.control_rate_hz if rate_hz is None else rate_hz
    if not control_rate_hz > 0:
        raise ScenarioError(f"--rate-hz {control_rate_hz}: must be > 0")
    if not speed > 0:
        raise ScenarioError(f"--speed {speed}: must be > 0")
    return AgentConfig(
        vehicle_id=vehicle.vehicle_id,
        role=vehicle.role,
        group=vehicle.group,
        pad_enu_m=(vehicle.pad_enu_m[0], vehicle.pad_enu_m[1]),
        has_gps=vehicle.has_gps,
        params=plan.params,
        control_rate_hz=control_rate_hz,
        speed=speed,
        paced=paced,
        connect_timeout_s=connect_timeout_s,
        limits=PhaseLimits(takeoff_altitude_m=plan.altitude_m, link_timeout_s=link_timeout_s),
        start_delay_s=plan.start_delay_s,
    )


def config_from_args(args: argparse.Namespace) -> tuple[AgentConfig, str, str]:
    """The agent's configuration, its mission name in the Zenoh keys and its autopilot URL; raises on bad input."""
    plan = load_agent_plan(args)
    if args.role is not None and args.role != plan.vehicle.role:
        vehicle = plan.vehicle
        raise ScenarioError(f"--role {args.role}: the plan has vehicle {vehicle.vehicle_id} as {vehicle.role}")
    config = agent_config(plan, rate_hz=args.rate_hz, speed=args.speed, paced=args.clock == "paced",
                          connect_timeout_s=args.connect_timeout, link_timeout_s=args.link_timeout)
    mission = validate_mission(args.mission or plan.mission)
    url = args.mavlink or f"udpin://0.0.0.0:{args.mavlink_base_port + config.vehicle_id - 1}"
    return config, mission, url


def mission_key(args: argparse.Namespace) -> MissionKey:
    """The key that signs this drone's states and checks the ground station's commands: ``--key-file``, or the
    one delivered with the plan."""
    if args.key_file is not None:
        return read_key_file(args.key_file)
    if args.plan is None:
        raise KeyFileError("--key-file: required without --plan (the mission key comes with the plan)")
    return read_key_file(args.plan.parent / KEY_FILE_NAME)


def _make_link(kind: str, url: str, control_rate_hz: float, has_gps: bool):  # noqa: ANN202 - an AutopilotLink
    """The MAVLink library's link; MAVSDK asks for the local position at the control rate, no faster, and for the
    global position (GLOBAL_POSITION_INT) only on a drone with GPS, the only one whose state message carries it."""
    if kind == "pymavlink":
        from vehicle_agents.autopilot_link_pymavlink import PymavlinkAutopilotLink

        return PymavlinkAutopilotLink(url)
    from vehicle_agents.autopilot_link_mavsdk import TELEMETRY_RATES_HZ, MavsdkAutopilotLink

    rates_hz = {**TELEMETRY_RATES_HZ, "position_velocity_ned": control_rate_hz}
    if not has_gps:
        rates_hz["position"] = -1.0
    return MavsdkAutopilotLink(url, rates_hz)


async def _run(agent: Agent) -> int:
    loop = asyncio.get_running_loop()
    for sig in (signal.SIGTERM, signal.SIGINT):
        loop.add_signal_handler(sig, agent.request_stop)
    return await agent.run()


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    cv2.setNumThreads(1)  # one small frame at a time: OpenCV's worker pool would only add thread wake-ups
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(name)s %(levelname)s %(message)s")
    try:
        config, mission, url = config_from_args(args)
        zenoh = zenoh_config_from_args(args)
        key = mission_key(args)
    except (ScenarioError, PlanFileError, KeyNameError, KeyFileError, ValueError) as exc:
        print(f"vehicle_agents: {exc}", file=sys.stderr)
        return EXIT_USAGE
    from vehicle_agents.core.sensed_neighbours import reads_ranging
    from vehicle_agents.swarm_link_zenoh import ZenohSwarmLink

    try:
        swarm = ZenohSwarmLink(config.vehicle_id, mission, zenoh, via_radio=args.neighbours == "radio",
                               key=key, relays=config.params.relay_max_hops > 0,
                               ranges=reads_ranging(config.params, config.has_gps))
    except ZenohOpenError as exc:
        print(f"vehicle_agents: vehicle {config.vehicle_id}: {exc}", file=sys.stderr)
        return EXIT_START_FAILED
    from vehicle_agents.sim_clock_link import SimClockLink

    sim_clock = SimClockLink(swarm.session, swarm.keys, config.vehicle_id)
    agent = Agent(config, _make_link(args.link, url, config.control_rate_hz, config.has_gps), swarm, sim_clock)
    code = asyncio.run(_run(agent))
    stats = agent.stats
    logging.getLogger("vehicle_agents").info(
        "vehicle %d exits with %d: %d control steps (%.1f Hz mission time), %d overruns, %d frames processed "
        "(perception %.2f / %.2f ms CPU per frame, p50 / p95), %d frames missed; dropped for their tag: %d commands, "
        "%d states; relayed copies refused: %d",
        config.vehicle_id, code, stats.control_steps, stats.control_rate_hz(), stats.overruns, stats.frames_processed,
        *stats.perception_cpu_ms(), stats.frames_dropped, swarm.command_verifier.dropped_total(),
        0 if swarm.link.verifier is None else swarm.link.verifier.dropped_total(), sum(agent.state.refused_copies))
    return code


if __name__ == "__main__":
    sys.exit(main())
