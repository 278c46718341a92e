"""One agent process against a real mock PX4 over loopback MAVLink (MAVSDK) and Zenoh.

The fleet, the simulator bridge and a Zenoh hub run in the test process; the agent is a real
``python -m vehicle_agents`` process, exactly as the mission starts it.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from comms.key_file import create_key_file
from comms.keys import MissionKeys
from comms.signing import GROUND_STATION, Signer, unsigned_body
from comms.swarm_link import wall_clock_us
from comms.messages import FLAG_OFFBOARD, MissionCommand, NeighbourState, decode, encode
from comms.zenoh_session import ZenohConfig, ZenohSession
from gcs.scenario import load_scenario
from mission_plan.plan_files import write_plan
from mission_plan.plans import agent_plan, fleet_plan
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.fleet import Fleet
from mock_autopilot.sim_bridge.__main__ import vehicle_configs, vehicle_truths
from mock_autopilot.sim_bridge.bridge import CameraStreamer, SimBridge
from mock_autopilot.world.config import flood_model_from_config

pytestmark = pytest.mark.integration
REPO = Path(__file__).resolve().parents[2]
SPEED = 2.0


def _start_agent(plan: Path, vehicle_id: int, base_port: int, hub: str, log: Path) -> subprocess.Popen[bytes]:
    args = [sys.executable, "-m", "vehicle_agents", "--plan", str(plan),
            "--mavlink", f"udpin://0.0.0.0:{base_port + vehicle_id - 1}", "--speed", str(SPEED), "--connect", hub]
    return subprocess.Popen(args, cwd=REPO, stdout=log.open("wb"), stderr=subprocess.STDOUT, start_new_session=True)


def _stop(proc: subprocess.Popen[bytes]) -> None:
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=10)


def _wait_state(states, vehicle_id: int, predicate, timeout_s: float, pump=None) -> NeighbourState | None:  # noqa: ANN001
    deadline = time.monotonic() + timeout_s
    latest = None
    while time.monotonic() < deadline:
        if pump is not None:
            pump()
        for item in states.drain():
            msg = decode(NeighbourState, unsigned_body(item.payload))
            if msg is not None and msg.sender_id == vehicle_id:
                latest = msg
        if latest is not None and predicate(latest):
            return latest
        time.sleep(0.02)
    return None


def test_agent_takes_off_flies_its_law_and_exits_when_its_vehicle_dies(
    tmp_path: Path, udp_ports: Callable[[int], int], zenoh_endpoint: Callable[[], str],
) -> None:
    scenario = load_scenario("circle")
    hub_ep, base, gcs, mission = zenoh_endpoint(), udp_ports(1), udp_ports(1), "agenttest"
    keys = MissionKeys(mission)
    flood = flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
    camera = CameraModel(scenario.camera.width_px, scenario.camera.height_px, scenario.camera.fov_deg)
    configs = vehicle_configs(fleet_plan(scenario, mission))[:1]
    plan = write_plan(tmp_path / "agent_1.json", agent_plan(scenario, 1, "improved", mission))
    ground_station = Signer(create_key_file(tmp_path / "mission.key"), GROUND_STATION)
    with Fleet(configs, base_port=base, gcs_port=gcs, speed=SPEED) as fleet, \
            ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        states = hub.subscribe(keys.state(1))
        alive = hub.subscribe_alive(keys.alive(1))
        bridge = SimBridge(hub, mission, 0.1, CameraStreamer(hub, mission, flood, camera, scenario.seed, 0.1))
        agent = _start_agent(plan, 1, base, hub_ep, tmp_path / "agent_1.log")
        try:
            pump = lambda: bridge.tick(fleet.clock.now_s(), vehicle_truths(fleet.truth(), fleet))  # noqa: E731
            hovering = _wait_state(states, 1, lambda m: m.has(FLAG_OFFBOARD) and m.altitude_m > 8.0, 60.0, pump)
            assert hovering is not None, (tmp_path / "agent_1.log").read_text()[-2000:]
            start_en = np.array(hovering.position_en_m)
            start = MissionCommand(seq=1, t_s=fleet.clock.now_s(), command="start", flood_clock_start_t_s=fleet.clock.now_s())
            hub.put(keys.command, ground_station.sign(encode(start), wall_clock_us()))
            moved = _wait_state(states, 1, lambda m: np.hypot(*(np.array(m.position_en_m) - start_en)) > 2.0, 30.0, pump)
            assert moved is not None, "the control law never moved the vehicle"
            assert moved.edge_points_en_m, "a boundary drone over the edge reports the edge points it sees"
            truth = fleet.truth().position_enu_m[0]
            assert abs(np.hypot(truth[0], truth[1]) - 12.0) < 3.0, f"boundary drone far from the edge: {truth}"

            alive.drain()
            fleet.kill(0)
            killed = time.monotonic()
            agent.wait(timeout=10.0)
            exited_after_s = time.monotonic() - killed
        finally:
            _stop(agent)
        log = (tmp_path / "agent_1.log").read_text()
        assert agent.returncode == 3, log[-2000:]
        assert exited_after_s < 3.0, f"agent noticed the dead vehicle after {exited_after_s:.2f} s"
        assert "vehicle lost" in log
        deadline = time.monotonic() + 3.0
        gone = False
        while time.monotonic() < deadline and not gone:
            gone = any(item.kind == "delete" for item in alive.drain())
            time.sleep(0.05)
        assert gone, "the agent's liveliness token must vanish when it leaves"
