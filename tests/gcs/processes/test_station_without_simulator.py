"""The ground station with no simulator: real processes of `python -m mock_autopilot` as the vehicles and
`python -m vehicle_agents` as their agents, as on real drones (no simulator bridge, no cameras, no radio emulator,
no ground truth). The station must bring the mission through its phases on what the GCS link and the agents say."""

from __future__ import annotations

import asyncio
import os
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from comms.key_file import create_key_file
from gcs.processes.ground_station import EXIT_OK, GroundStation
from gcs.processes.launch import ProcessOptions
from gcs.scenario import load_scenario

pytestmark = pytest.mark.integration
REPO = Path(__file__).resolve().parents[3]
TWO_BOUNDARY_DRONES = ("fleet.boundary_per_group=1", "fleet.leaders=0", "fleet.follower_layers=[]")


def _read(path: Path) -> str:
    return path.read_text() if path.exists() else ""


@pytest.fixture
def processes() -> Iterator[Callable[[list[str], Path], subprocess.Popen]]:
    """Start Python modules from the repository; every one is stopped at teardown, whatever happened."""
    started: list[subprocess.Popen] = []

    def start(args: list[str], log: Path) -> subprocess.Popen:
        env = dict(os.environ, PYTHONPATH=str(REPO))
        with log.open("w") as out:
            started.append(subprocess.Popen([sys.executable, "-m", *args], cwd=REPO, env=env, stdout=out,
                                            stderr=subprocess.STDOUT))
        return started[-1]

    yield start
    for p in started:
        if p.poll() is None:
            p.terminate()
    for p in started:
        try:
            p.wait(timeout=10)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait(timeout=10)


def test_station_flies_a_mission_with_mock_px4_vehicles_and_no_simulator(
    tmp_path: Path, udp_ports: Callable[[int], int], zenoh_endpoint: Callable[[], str],
    processes: Callable[[list[str], Path], subprocess.Popen],
) -> None:
    scenario = load_scenario("circle", TWO_BOUNDARY_DRONES)
    base, gcs, endpoint = udp_ports(2), udp_ports(1), zenoh_endpoint()
    out = tmp_path / "run"
    out.mkdir()
    key_file = tmp_path / "mission.key"
    create_key_file(key_file)  # handed to the drones and the station beforehand
    options = ProcessOptions(scenario_arg="circle", overrides=TWO_BOUNDARY_DRONES, duration_s=3.0, out_dir=out,
                             mission="nosim", mavlink_base_port=base, gcs_port=gcs, zenoh_endpoint=endpoint,
                             live=False, startup_timeout_s=60.0, takeoff_timeout_s=90.0, key_file=key_file)
    station = GroundStation(scenario, options, out, simulated=False)
    result: dict[str, int] = {}
    runner = threading.Thread(target=lambda: result.setdefault("code", asyncio.run(station.run())))
    runner.start()
    try:
        deadline = time.monotonic() + 30.0  # the agents join the station's Zenoh hub: it must be open first
        while "no simulator" not in _read(out / "events.log") and time.monotonic() < deadline:
            time.sleep(0.1)
        vehicles = processes(["mock_autopilot", "--vehicles", "2", "--base-port", str(base), "--gcs-port", str(gcs)],
                             tmp_path / "vehicles.log")
        for vid in (1, 2):
            overrides = [arg for override in TWO_BOUNDARY_DRONES for arg in ("--set", override)]
            processes(["vehicle_agents", "--scenario", "circle", *overrides, "--id", str(vid), "--mission", "nosim",
                       "--mavlink-base-port", str(base), "--neighbours", "direct", "--connect", endpoint,
                       "--key-file", str(key_file)],
                      tmp_path / f"agent_{vid}.log")
        runner.join(timeout=240.0)
    finally:
        if runner.is_alive():
            station.interrupt()
            runner.join(timeout=30.0)
    code = result.get("code")
    events = _read(out / "events.log")
    assert code == EXIT_OK, events
    assert vehicles.poll() is None, "the vehicles outlive the station: it did not start them and does not stop them"
    assert "no simulator" in events and "flood clock starts" in events and "mission complete" in events
    assert station.evaluation is None and station.children is None
    assert (out / "vehicle_1.tlog").stat().st_size > 0 and (out / "vehicle_2.tlog").stat().st_size > 0
