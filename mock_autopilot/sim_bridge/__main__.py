"""``python -m mock_autopilot.sim_bridge --plan fleet.json`` (or ``--scenario circle``): the mock PX4 fleet, bridged.

Starts one simulated PX4 per planned vehicle (pads, GPS, home, velocity limits and response time from the fleet
plan; system id = vehicle id; onboard link to ``--base-port + i``, GCS link to ``--gcs-port``) and, in the same
process, the simulator bridge that publishes ground truth (and, unless ``--cameras none``, each vehicle's camera)
over Zenoh. ``--clock paced`` (what the ground station runs) holds the fleet's clock at each control tick until the
camera and radio processes and every agent have acknowledged it (:mod:`mock_autopilot.pacing`); ``--clock free``
(the default here, for a fleet driven by hand) lets it run at ``--speed``. The ground station writes the fleet plan (``<run>/plan/fleet.json``); ``--scenario NAME`` resolves a
scenario locally through ``mission_plan`` (not for "auto" pads). Runs until SIGTERM / Ctrl-C. Exit codes: 0
stopped, 1 a port is taken or Zenoh is unreachable, 2 bad arguments or plan.
"""

from __future__ import annotations

import argparse
import logging
import math
import signal
import sys
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from comms.cli_args import add_zenoh_arguments, zenoh_config_from_args
from comms.keys import KeyNameError, validate_mission
from comms.px4 import Px4Mode
from comms.zenoh_session import ZenohConfig, ZenohOpenError, ZenohSession
from mission_plan.plan_files import PlanFileError, plan_or_scenario
from mission_plan.plans import FleetPlan, fleet_plan
from mission_plan.roles import Role
from mission_plan.table_fields import ScenarioError
from mock_autopilot.backends.px4 import px4_vehicle_configs
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.faults import FaultSpec, FaultSpecError, parse_fault
from mock_autopilot.fleet import Fleet, FleetTruth
from mock_autopilot.pacing import Pacer
from mock_autopilot.ports import LinkHosts, link_hosts
from mock_autopilot.px4_streams import DEFAULT_PROFILE
from mock_autopilot.sim_bridge.bridge import CameraStreamer, SimBridge, VehicleTruth, camera_users
from mock_autopilot.sim_bridge.pace_keeper import PaceKeeper
from mock_autopilot.vehicle import VehicleConfig
from mock_autopilot.weather_model import Weather
from mock_autopilot.world.config import flood_model_from_config
from mock_autopilot.world.flood_model import FloodModel
from mock_autopilot.world.ground import relative_ground_m

log = logging.getLogger("mock_autopilot.sim_bridge")


def vehicle_configs(plan: FleetPlan) -> list[VehicleConfig]:
    """One PX4 per planned vehicle; the plan's dynamics become the PX4 parameters that set them (and the plant's
    response time, which is not a PX4 parameter)."""
    return px4_vehicle_configs(plan.kinematics, plan.altitude_m, [v.pad_enu_m for v in plan.vehicles],
                               has_gps=[v.has_gps for v in plan.vehicles], home=plan.home,
                               system_ids=[v.vehicle_id for v in plan.vehicles], stream_profile=DEFAULT_PROFILE,
                               weather=Weather(plan.wind, plan.sensors, plan.seed, plan.altitude_m))


def load_fleet_plan(plan_path: Path | None, scenario: str | None, overrides: Sequence[str]) -> FleetPlan:
    """The ``--plan`` file, or the ``--scenario`` (default circle) resolved locally through mission_plan."""
    return plan_or_scenario(plan_path, scenario, overrides, FleetPlan, fleet_plan)


def vehicle_truths(truth: FleetTruth, fleet: Fleet) -> list[VehicleTruth]:
    """Each vehicle's truth with the body's (roll, pitch) its ATTITUDE reports (the camera is fixed to the body)."""
    return [
        VehicleTruth(int(truth.system_ids[i]), truth.position_enu_m[i], truth.velocity_enu_mps[i],
                     float(truth.yaw_ned_rad[i]), bool(truth.alive[i]), fleet.vehicles[i].tilt_rad())
        for i in range(len(truth.system_ids))
    ]


def set_ground_below(fleet: Fleet, truth: FleetTruth, flood: FloodModel) -> None:
    """Tell each vehicle how high the ground below it is, for its DISTANCE_SENSOR."""
    ground = relative_ground_m(flood, np.asarray(truth.position_enu_m, float)[:, :2])
    for vehicle, ground_m in zip(fleet.vehicles, ground):
        vehicle.ground_below_enu_m = float(ground_m)


def setpoint_ages(fleet: Fleet, truth: FleetTruth, now_s: float) -> list[float]:
    """Age [mission s] of the newest offboard setpoint each vehicle in OFFBOARD holds: what PX4's offboard
    watchdog (COM_OF_LOSS_T) looks at. For the benchmark; read-only use of the vehicle's receive time."""
    ages = []
    for vehicle, mode in zip(fleet.vehicles, truth.modes):
        received_s = getattr(vehicle, "_setpoint_t_s", None)
        if mode == Px4Mode.OFFBOARD.value and received_s is not None and np.isfinite(received_s):
            ages.append(now_s - received_s)
    return ages


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m mock_autopilot.sim_bridge",
                                description="A planned mock PX4 fleet with camera frames and truth over Zenoh.")
    p.add_argument("--plan", type=Path, metavar="FILE", help="the fleet plan (JSON) the ground station wrote")
    p.add_argument("--scenario", help="without --plan: bundled scenario name or TOML path (default circle)")
    p.add_argument("--set", action="append", default=[], dest="overrides", metavar="KEY=VALUE",
                   help="with --scenario: override a scenario parameter")
    p.add_argument("--mission", help="mission name in the Zenoh keys (default: the plan's)")
    p.add_argument("--speed", type=float, default=1.0,
                   help="simulated seconds per wall second (with a paced clock: the most it may run at)")
    p.add_argument("--clock", choices=("paced", "free"), default="free",
                   help="paced: hold each control tick until the cameras, the radio and every agent have done theirs; "
                        "free: run at --speed whatever the participants do")
    p.add_argument("--agent-timeout-s", type=float, default=2.0,
                   help="paced clock: wall seconds a participant may hold a tick before the clock goes on without it")
    p.add_argument("--base-port", type=int, default=14540)
    p.add_argument("--gcs-port", type=int, default=14550)
    p.add_argument("--bind", default=None, metavar="ADDR",
                   help="address the vehicles' MAVLink sockets bind (default 127.0.0.1; 0.0.0.0 for other hosts)")
    p.add_argument("--onboard-partner", action="append", default=[], metavar="IDS=IP",
                   help="send these vehicles' onboard link to their companion computer at IP (PX4: mavlink start -t "
                        "IP), e.g. 1-4=10.0.0.2")
    p.add_argument("--camera-hz", type=float,
                   help="camera frame rate in mission time (default: the plan's camera rate)")
    p.add_argument("--truth-hz", type=float, help="ground-truth rate in mission time (default: the control rate)")
    p.add_argument("--cameras", choices=(Role.BOUNDARY.value, "all", "none"), default=Role.BOUNDARY.value,
                   help="whose camera this process streams: the boundary drones (the only law that uses images), "
                        "all, or none (python -m mock_autopilot.sim_bridge.cameras streams them instead)")
    p.add_argument("--fault", action="append", default=[], metavar="KIND:INSTANCE[:VALUE]@T",
                   help="scheduled fault (see python -m mock_autopilot --help)")
    p.add_argument("--log-level", default="INFO")
    add_zenoh_arguments(p)
    return p


@dataclass(frozen=True)
class _Setup:
    """The command line checked against the plan: everything :func:`main` needs before it binds a port."""

    plan: FleetPlan
    mission: str
    zenoh: ZenohConfig
    faults: list[FaultSpec]
    camera_hz: float
    truth_hz: float
    flood: FloodModel
    hosts: LinkHosts


def _setup(args: argparse.Namespace) -> _Setup:
    """Load the plan and check the options; every failure is a ``ValueError`` (or a plan/scenario error) that
    :func:`main` turns into exit 2."""
    plan = load_fleet_plan(args.plan, args.scenario, args.overrides)
    mission = validate_mission(args.mission or plan.mission)
    zenoh = zenoh_config_from_args(args)
    faults = [parse_fault(text) for text in args.fault]
    if not args.speed > 0:
        raise ValueError(f"--speed {args.speed}: must be > 0")
    if not args.agent_timeout_s > 0:
        raise ValueError(f"--agent-timeout-s {args.agent_timeout_s}: must be > 0")
    if args.clock == "paced" and args.cameras != "none":
        raise ValueError("--clock paced: run the cameras in their own process (--cameras none)")
    camera_hz = args.camera_hz or plan.camera.rate_hz
    truth_hz = args.truth_hz or plan.control_rate_hz
    if not (camera_hz > 0 and truth_hz > 0):
        raise ValueError("--camera-hz and --truth-hz must be > 0")
    world = plan.world
    # The cameras render the flood and the rangefinders measure its ground (flat but for the hydro model).
    flood = flood_model_from_config(world.flood, seed=world.seed, base_dir=world.source_dir)
    return _Setup(plan, mission, zenoh, faults, camera_hz, truth_hz, flood, link_hosts(args.bind, args.onboard_partner))


def _serve(args: argparse.Namespace, setup: _Setup, fleet: Fleet, pacer: Pacer, session: ZenohSession,
           stop: threading.Event) -> None:
    """Publish truth (and camera frames, unless another process streams them) until ``stop``; the paced clock's
    keeper publishes truth at each released tick, the free clock on the bridge's own schedule."""
    plan, flood = setup.plan, setup.flood
    streamer = None
    if args.cameras != "none":
        camera = CameraModel(plan.camera.width_px, plan.camera.height_px, plan.camera.fov_deg)
        streamer = CameraStreamer(
            session, setup.mission, flood, camera, plan.seed, 1.0 / setup.camera_hz,
            camera_users({v.vehicle_id: v.role for v in plan.vehicles}, args.cameras),
            on_flood_start=lambda t: log.info("flood clock started at mission time %.2f s", t))
    bridge = SimBridge(session, setup.mission, 1.0 / setup.truth_hz, streamer)
    setpoint_ages_s: list[float] = []

    def publish_truth(t_s: float) -> None:
        truth = fleet.truth()
        set_ground_below(fleet, truth, flood)
        bridge.publish_truth(t_s, vehicle_truths(truth, fleet))
        setpoint_ages_s.extend(setpoint_ages(fleet, truth, t_s))

    keeper = PaceKeeper(session, setup.mission, pacer, fleet.clock.now_s, lambda: fleet.last_tick_t_s,
                        fleet.set_gate, publish_truth)
    log.info("fleet of %d vehicles up (speed x%g, %s clock), bridge publishing on floodwatch/%s",
             len(plan.vehicles), args.speed, args.clock, setup.mission)
    while not stop.is_set():
        keeper.poll()
        if pacer.paced:
            keeper.wait(keeper.next_wait_s())
            continue
        now_s = fleet.clock.now_s()
        truth = fleet.truth()
        set_ground_below(fleet, truth, flood)
        bridge.tick(now_s, vehicle_truths(truth, fleet))
        setpoint_ages_s.extend(setpoint_ages(fleet, truth, fleet.clock.now_s()))
        wait_s = fleet.clock.wall_delay_s(max(0.0, bridge.next_due_s() - fleet.clock.now_s()))
        stop.wait(min(wait_s, 0.05))
    _log_summary(keeper, bridge, streamer, setpoint_ages_s)


def _log_summary(keeper: PaceKeeper, bridge: SimBridge, streamer: CameraStreamer | None,
                 setpoint_ages_s: list[float]) -> None:
    """The clock's achieved factor, what the bridge sent, and the setpoint age PX4's offboard watchdog saw."""
    final = keeper.report()
    log.info("clock: %.1f s simulated in %.1f s wall (%.2fx real time, %s), held %.1f s waiting",
             final.t_s, final.wall_s, final.real_time_factor, "paced" if final.paced else "free",
             final.held_wall_s)
    log.info("bridge sent %d truth samples", bridge.truths_sent)
    if streamer is not None:
        log.info("bridge %s", streamer.summary())
    if setpoint_ages_s:
        p50, p99 = np.percentile(setpoint_ages_s, [50, 99])
        log.info("setpoint age at the autopilot [mission s]: p50 %.4f p99 %.4f max %.4f (%d samples)",
                 p50, p99, max(setpoint_ages_s), len(setpoint_ages_s))


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(name)s %(levelname)s %(message)s")
    try:
        setup = _setup(args)
    except (ScenarioError, PlanFileError, KeyNameError, FaultSpecError, ValueError) as exc:
        print(f"sim_bridge: {exc}", file=sys.stderr)
        return 2
    # OpenCV parallelises each remap over its own thread pool; on a machine already saturated by the agents, every
    # frame then waits for pool threads that are not scheduled (measured: 15 ms wall for 3 ms of CPU per frame).
    cv2.setNumThreads(1)
    stop = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())
    pacer = Pacer(1.0 / setup.truth_hz, args.agent_timeout_s, paced=args.clock == "paced")
    fleet = Fleet(vehicle_configs(setup.plan), base_port=args.base_port, gcs_port=args.gcs_port, speed=args.speed,
                  host=setup.hosts, faults=setup.faults, initial_gate_s=pacer.gate_s if pacer.paced else math.inf)
    try:
        fleet.start()
    except OSError as exc:
        print(f"sim_bridge: cannot bind the fleet's MAVLink ports: {exc}", file=sys.stderr)
        return 1
    try:
        try:
            session = ZenohSession(setup.zenoh)
        except ZenohOpenError as exc:
            print(f"sim_bridge: {exc}", file=sys.stderr)
            return 1
        with session:
            _serve(args, setup, fleet, pacer, session, stop)
    finally:
        fleet.stop()
    return 0


if __name__ == "__main__":
    sys.exit(main())
