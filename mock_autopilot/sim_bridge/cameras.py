"""``python -m mock_autopilot.sim_bridge.cameras --plan cameras.json``: the camera streams in a process of their own.

Fed by the ground truth the fleet's process publishes, it renders each streaming vehicle's downward camera at the
camera rate and publishes the frames (see :class:`mock_autopilot.sim_bridge.bridge.CameraStreamer`), and the
relative-position measurements of the drones without GPS while their odometry drifts
(:class:`mock_autopilot.sim_bridge.ranging_streamer.RangingStreamer`). Keeping the
renderer out of the fleet's process gives it its own CPU share and interpreter lock: in one process, the fleet's
MAVLink thread and the renderer slowed each other down (docs/BENCHMARKS.md, Mission). The cameras plan (the
ground station writes ``<run>/plan/cameras.json``) gives the flood table, seed, DEM folder, camera and each
vehicle's role; ``--scenario NAME`` resolves a scenario locally through ``mission_plan`` (not for "auto" pads).
After each truth it has handled (frames due by then rendered and published) it acknowledges the truth's time on
``sim/pace/cameras``, which a paced simulation clock waits for (:mod:`mock_autopilot.pacing`), and once a wall second
it publishes its achieved frame rate (``CameraStats``). Runs until SIGTERM / Ctrl-C.
"""

from __future__ import annotations

import argparse
import logging
import signal
import sys
import threading
import time
from collections.abc import Sequence
from pathlib import Path

import cv2

from comms.cli_args import add_zenoh_arguments, zenoh_config_from_args
from comms.keys import KeyNameError, MissionKeys, validate_mission
from comms.messages import CameraStats, GroundTruth, PaceAck, decode, encode
from comms.zenoh_session import ZenohOpenError, ZenohSession
from mission_plan.plan_files import PlanFileError, plan_or_scenario
from mission_plan.plans import CamerasPlan, cameras_plan
from mission_plan.roles import Role
from mission_plan.table_fields import ScenarioError
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.sim_bridge.bridge import CameraStreamer, camera_users, vehicles_from_truth
from mock_autopilot.sim_bridge.ranging_streamer import RangingStreamer
from mock_autopilot.world.config import flood_model_from_config

log = logging.getLogger("mock_autopilot.sim_bridge.cameras")


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m mock_autopilot.sim_bridge.cameras",
                                description="Render and stream the vehicles' camera frames from published truth.")
    p.add_argument("--plan", type=Path, metavar="FILE", help="the cameras plan (JSON) the ground station wrote")
    p.add_argument("--scenario", help="without --plan: bundled scenario name or TOML path (default circle)")
    p.add_argument("--set", action="append", default=[], dest="overrides", metavar="KEY=VALUE",
                   help="with --scenario: override a scenario parameter")
    p.add_argument("--mission", help="mission name in the Zenoh keys (default: the plan's)")
    p.add_argument("--camera-hz", type=float, help="frame rate in mission time (default: the plan's camera rate)")
    p.add_argument("--cameras", choices=(Role.BOUNDARY.value, "all"), default=Role.BOUNDARY.value)
    p.add_argument("--log-level", default="INFO")
    add_zenoh_arguments(p)
    return p


def load_cameras_plan(plan_path: Path | None, scenario: str | None, overrides: Sequence[str]) -> CamerasPlan:
    """The ``--plan`` file, or the ``--scenario`` (default circle) resolved locally through mission_plan."""
    return plan_or_scenario(plan_path, scenario, overrides, CamerasPlan, cameras_plan)


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(name)s %(levelname)s %(message)s")
    try:
        plan = load_cameras_plan(args.plan, args.scenario, args.overrides)
        mission = validate_mission(args.mission or plan.mission)
        zenoh = zenoh_config_from_args(args)
        camera_hz = args.camera_hz or plan.camera.rate_hz
        if not camera_hz > 0:
            raise ValueError("--camera-hz must be > 0")
        flood = flood_model_from_config(plan.world.flood, seed=plan.world.seed, base_dir=plan.world.source_dir)
    except (ScenarioError, PlanFileError, KeyNameError, ValueError) as exc:
        print(f"cameras: {exc}", file=sys.stderr)
        return 2
    cv2.setNumThreads(1)  # one frame at a time on a busy machine; OpenCV's pool only adds waiting
    camera = CameraModel(plan.camera.width_px, plan.camera.height_px, plan.camera.fov_deg)
    stop = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())
    try:
        session = ZenohSession(zenoh)
    except ZenohOpenError as exc:
        print(f"cameras: {exc}", file=sys.stderr)
        return 1
    with session:
        keys = MissionKeys(mission)
        truth_buf = session.subscribe(keys.truth)
        session.declare_alive(keys.alive("cameras"))
        streamer = CameraStreamer(session, mission, flood, camera, plan.world.seed, 1.0 / camera_hz,
                                  camera_users(plan.roles, args.cameras),
                                  on_flood_start=lambda t: log.info("flood clock started at mission time %.2f s", t),
                                  imaging=plan.imaging, wind_en_mps=plan.wind_en_mps)
        ranging = RangingStreamer(session, mission, plan.sensors, plan.world.seed, list(plan.roles))
        latest_t_s = -1.0
        next_stats_wall_s = time.monotonic() + 1.0
        while not stop.is_set():
            if truth_buf.wait(0.2):
                for item in truth_buf.drain():
                    truth = decode(GroundTruth, item.payload)
                    if truth is None or truth.t_s <= latest_t_s:
                        continue
                    latest_t_s = truth.t_s
                    vehicles = vehicles_from_truth(truth)
                    streamer.stream(truth.t_s, vehicles)
                    ranging.stream(truth.t_s, vehicles)
                    session.put(keys.pace("cameras"), encode(PaceAck(participant="cameras", t_s=truth.t_s)))
            if time.monotonic() >= next_stats_wall_s and latest_t_s >= 0:
                session.put(keys.camera_stats, encode(CameraStats(
                    t_s=latest_t_s, frames_sent=streamer.frames_sent, frame_rate_hz=streamer.frame_rate_hz(),
                    nominal_rate_hz=1.0 / streamer.camera_period_s)))
                next_stats_wall_s = time.monotonic() + 1.0
        log.info("cameras %s; %d ranging measurements", streamer.summary(), ranging.sent)
    return 0


if __name__ == "__main__":
    sys.exit(main())
