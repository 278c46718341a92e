"""Whole missions with the processes engine over real loopback MAVLink and Zenoh: metrics, faults, bad input.

Every test takes its own block of free ports from the ``udp_ports`` fixture (never a user's 14540/14550/7447, never
another test's), and checks that no process outlives the run.
"""

from __future__ import annotations

import asyncio
import json
import os
import re
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from gcs.metrics.agreement import disagreements
from gcs.processes import ProcessOptions, run_processes
from gcs.processes.ground_station import GroundStation
from gcs.scenario import load_scenario

pytestmark = [pytest.mark.integration, pytest.mark.e2e]

REPO = Path(__file__).resolve().parents[2]
CI_SPEED = 1.0
"""The speed factor a loaded 2-core machine holds with 13 agents, the fleet+camera bridge and the radio: at x2 the
bridge cannot render every camera frame in time (docs/BENCHMARKS.md, Mission (processes engine))."""


def pids_of_run(out_dir: Path) -> dict[str, int]:
    path = out_dir / "processes.json"
    return json.loads(path.read_text()) if path.exists() else {}


def alive_pids(pids: dict[str, int]) -> dict[str, int]:
    """Those of ``pids`` that still exist and are not zombies."""
    alive = {}
    for name, pid in pids.items():
        try:
            status = Path(f"/proc/{pid}/status").read_text()
        except OSError:
            continue
        if "\nState:\tZ" not in status:
            alive[name] = pid
    return alive


def assert_no_orphans(out_dir: Path, wait_s: float = 5.0) -> None:
    pids = pids_of_run(out_dir)
    assert pids, "the run recorded no process ids"
    deadline = time.monotonic() + wait_s
    while alive_pids(pids) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert alive_pids(pids) == {}, f"orphan processes left behind: {alive_pids(pids)}"


PORT_BLOCK = 61
"""A mission's ports from its base: vehicles base + i, the GCS link base + 50, the Zenoh hub base + 60."""


def _options(out_dir: Path, base: int, **changes: object) -> ProcessOptions:
    values: dict[str, object] = dict(
        scenario_arg="circle", mode="improved", speed=CI_SPEED, duration_s=20.0, out_dir=out_dir,
        mission=f"e2e{base}", mavlink_base_port=base, gcs_port=base + 50, zenoh_endpoint=f"tcp/127.0.0.1:{base + 60}",
        live=False,
    )
    values.update(changes)
    return ProcessOptions(**values)  # type: ignore[arg-type]


def _mavlogdump_types(tlog: Path) -> set[str]:
    """Message types in a .tlog as pymavlink's own mavlogdump.py prints them."""
    out = subprocess.run([sys.executable, "-m", "pymavlink.tools.mavlogdump", "--types", "HEARTBEAT,LOCAL_POSITION_NED",
                          str(tlog)], capture_output=True, text=True, timeout=120, check=True).stdout
    return {line.split()[2] for line in out.splitlines() if len(line.split()) > 2}


def _check_outputs(out: Path, min_duration_s: float) -> dict[str, object]:
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["engine"] == "processes"
    assert metrics["summary"]["duration_s"] >= min_duration_s
    geojson = json.loads((out / "polygons.geojson").read_text())
    assert geojson["type"] == "FeatureCollection" and len(geojson["features"]) >= min_duration_s / 2
    assert (out / "polygons.kml").stat().st_size > 0 and (out / "trajectories.png").stat().st_size > 0
    for vid in (1, 9, 13):
        assert {"HEARTBEAT", "LOCAL_POSITION_NED"} <= _mavlogdump_types(out / f"vehicle_{vid}.tlog")
    events = (out / "events.log").read_text()
    assert "flood clock starts" in events and "mission complete" in events
    # every agent wrote its exit report (an honest run refuses no relayed copy), read back into both outputs
    assert "relayed copies refused as impossible: 0 by the vehicles\n" in events
    assert metrics["summary"]["relayed_copies_refused"] == 0 and metrics["summary"]["relayed_copies_refused_ground"] is None
    return metrics


def test_readme_mission_command_improved_meets_targets(tmp_path: Path, mission_cli, udp_ports) -> None:  # noqa: ANN001
    """The README's mission command (improved mode, shortened, own ports): the metrics say the mission worked."""
    out = tmp_path / "run"
    base = udp_ports(PORT_BLOCK)
    hub = f"tcp/127.0.0.1:{base + 60}"
    proc = mission_cli(["circle", "--mode", "improved", "--speed", str(CI_SPEED), "--duration", "20", "--out", str(out),
                        "--base-port", str(base), "--gcs-port", str(base + 50), "--no-live"], hub)
    polygons, states = _listen_to_public_keys(hub, "circle", proc)
    stdout, stderr = proc.communicate(timeout=240)
    assert proc.returncode == 0, stdout[-2000:] + stderr[-2000:]
    assert "mission complete" in stdout
    assert polygons and polygons[-1].properties.area_m2 > 400.0, "the rescue centre's polygon key stayed silent"
    lon, lat = polygons[-1].geometry.coordinates[0][0]
    assert abs(lat - 47.3977) < 0.001 and abs(lon - 8.5456) < 0.001
    assert set(states) == set(range(1, 14)), "every agent publishes its state on its public key"
    assert_no_orphans(out)
    s = _check_outputs(out, 18.0)["summary"]
    assert s["encircle_time_s"] is not None and s["encircle_time_s"] <= 20.0  # type: ignore[index]
    assert s["polygon_iou_final"] >= 0.95  # type: ignore[index]
    assert s["min_pairwise_distance_m"] >= 1.0 and s["near_miss_pairs"] == 0  # type: ignore[index]
    assert s["tracking_rms_last_10s_m"] <= 1.0  # type: ignore[index]


@pytest.mark.slow
def test_readme_mission_command_full_length_real_time(tmp_path: Path, mission_cli, udp_ports) -> None:  # noqa: ANN001
    """The README's first command as a user runs it (improved mode, 60 s, real time), only the ports moved."""
    out = tmp_path / "run"
    base = udp_ports(PORT_BLOCK)
    proc = mission_cli(["circle", "--out", str(out), "--base-port", str(base), "--gcs-port", str(base + 50),
                        "--no-live"],
                       f"tcp/127.0.0.1:{base + 60}")
    stdout, stderr = proc.communicate(timeout=400)
    assert proc.returncode == 0, stdout[-2000:] + stderr[-2000:]
    assert_no_orphans(out)
    s = _check_outputs(out, 58.0)["summary"]
    assert s["polygon_iou_final"] >= 0.95  # type: ignore[index]
    assert s["min_pairwise_distance_m"] >= 1.0 and s["near_miss_pairs"] == 0  # type: ignore[index]


@pytest.mark.slow
@pytest.mark.parametrize("scenario", ["ellipse", "nonconvex", "drift"])
def test_other_scenarios_run_over_processes(tmp_path: Path, scenario: str, udp_ports) -> None:  # noqa: ANN001
    """Every lockstep scenario also flies here (shortened); the caged polygon still overlaps the true flood."""
    out = tmp_path / "run"
    options = _options(out, udp_ports(PORT_BLOCK), scenario_arg=scenario, duration_s=30.0)
    code = run_processes(load_scenario(scenario), options)
    assert code == 0, _read(out / "events.log")[-3000:]
    assert_no_orphans(out)
    s = json.loads((out / "metrics.json").read_text())["summary"]
    assert s["polygon_iou_final"] >= 0.8 and s["min_pairwise_distance_m"] >= 1.0


@pytest.mark.slow
def test_processes_engine_matches_lockstep_on_circle_improved(
    tmp_path: Path, mission_cli, udp_ports: Callable[[int], int],
) -> None:  # noqa: ANN001
    """The done-when check: the same mission through both engines, which run the same onboard core, the lockstep
    one on the mock PX4 backend; metrics agree within gcs.metrics.agreement's tolerances (bench/mission_compare.py
    prints the same comparison for every small scenario)."""
    summaries = {}
    for engine, extra in (("lockstep", ["--backend", "px4"]), ("processes", [])):
        out = tmp_path / engine
        base = udp_ports(PORT_BLOCK)
        proc = mission_cli(["circle", "--engine", engine, "--mode", "improved", "--seed", "1", "--out", str(out),
                            "--no-live", "--base-port", str(base), "--gcs-port", str(base + 50), *extra],
                           f"tcp/127.0.0.1:{base + 60}")
        stdout, stderr = proc.communicate(timeout=600)
        assert proc.returncode == 0, stdout[-2000:] + stderr[-2000:]
        summaries[engine] = json.loads((out / "metrics.json").read_text())["summary"]
    assert disagreements(summaries["lockstep"], summaries["processes"]) == []
    assert summaries["processes"]["polygon_iou_final"] >= 0.95 and summaries["processes"]["near_miss_pairs"] == 0


def test_agent_killed_mid_mission_is_reported_and_swarm_goes_on(tmp_path: Path, udp_ports) -> None:  # noqa: ANN001
    """kill -9 of a boundary agent: the GCS reports it within 2 s, its vehicle falls back, the mission completes."""
    out = tmp_path / "run"
    scenario = load_scenario("circle")
    options = _options(out, udp_ports(PORT_BLOCK), duration_s=22.0)
    station = GroundStation(scenario, options, _mkdir(out))
    result: dict[str, int] = {}
    runner = threading.Thread(target=lambda: result.setdefault("code", _run(station)))
    runner.start()
    try:
        deadline = time.monotonic() + 120.0
        while time.monotonic() < deadline and not (station.phase == "mission" and station.flood_time_s() > 8.0):
            time.sleep(0.1)
        assert station.phase == "mission", (out / "events.log").read_text()[-2000:]
        victim = pids_of_run(out)["agent_3"]
        os.kill(victim, signal.SIGKILL)
        killed_wall = time.monotonic()
        while time.monotonic() - killed_wall < 2.0 and 3 not in station.lost:
            time.sleep(0.02)
        reported_after_s = time.monotonic() - killed_wall
    finally:
        runner.join(timeout=180.0)
        if runner.is_alive():
            station.interrupt()
            runner.join(timeout=30.0)
    assert result.get("code") == 0, (out / "events.log").read_text()[-3000:]
    assert reported_after_s < 2.0, f"agent loss reported after {reported_after_s:.2f} s"
    assert_no_orphans(out)
    events = (out / "events.log").read_text()
    assert "agent 3 lost" in events
    after_kill = events[events.index("agent 3 lost"):]
    fallback = re.search(r"vehicle 3: armed, mode (?!OFFBOARD)(\S+)", after_kill)
    assert fallback is not None, f"vehicle 3 never left OFFBOARD after its agent died (COM_OF_LOSS_T): {after_kill[:2000]}"
    metrics = json.loads((out / "metrics.json").read_text())
    losses = [loss for loss in metrics["losses"] if loss["vehicle_id"] == 3]
    assert losses, metrics["losses"]
    assert "unknown for vehicles 3 (no exit report)" in events  # killed: it never wrote its count
    refused = {vid: v["relayed_copies_refused"] for vid, v in metrics["per_vehicle"].items()}
    assert refused["3"] is None and refused["1"] == 0, refused
    # The survivors re-space past the unheard, hovering vehicle; measured 1.2-1.45 m closest approach at x1 (docs),
    # so only a real collision (< 0.5 m between live vehicles) fails here.
    assert metrics["summary"]["min_pairwise_distance_m"] >= 0.5, metrics["summary"]
    assert losses[0]["recovery_time_s"] is not None and losses[0]["recovery_time_s"] < 15.0, losses


@pytest.mark.slow
def test_vehicle_killed_mid_mission_its_agent_leaves_and_the_gcs_reports_it(
    tmp_path: Path, udp_ports: Callable[[int], int],
) -> None:
    """Fault injection kills vehicle 6 (instance 5) in the fleet: no more heartbeats, its agent notices and exits
    (code 3, vehicle lost), the ground station reports both, the mission completes."""
    out = tmp_path / "run"
    options = _options(out, udp_ports(PORT_BLOCK), duration_s=25.0, sim_faults=("kill:5@30",))
    code = run_processes(load_scenario("circle"), options)
    events = _read(out / "events.log")
    assert code == 0, events[-3000:]
    assert_no_orphans(out)
    assert "vehicle 6 lost: no heartbeat" in events, events[-3000:]
    assert "agent 6 exited with code 3" in events, events[-3000:]
    assert "vehicle lost" in _read(out / "agent_6.log")
    agent_left_t_s = _event_mission_time(events, "agent 6 lost")  # its liveliness token vanished as it exited
    assert agent_left_t_s - 30.0 < 3.0, f"the agent left {agent_left_t_s - 30.0:.2f} s after its vehicle died"
    metrics = json.loads((out / "metrics.json").read_text())
    assert [loss["vehicle_id"] for loss in metrics["losses"]] == [6]


def test_busy_zenoh_port_fails_cleanly(tmp_path: Path, udp_ports) -> None:  # noqa: ANN001
    out = tmp_path / "run"
    options = _options(out, udp_ports(PORT_BLOCK))
    hub_port = int(options.zenoh_endpoint.rsplit(":", 1)[1])
    blocker = socket.socket(socket.AF_INET, socket.SOCK_STREAM)  # the test blocks the very port it chose
    blocker.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    blocker.bind(("127.0.0.1", hub_port))
    blocker.listen(1)
    try:
        code = run_processes(load_scenario("circle"), options)
    finally:
        blocker.close()
    assert code == 1
    assert f"tcp/127.0.0.1:{hub_port} is not free" in _read(out / "events.log")
    assert pids_of_run(out) == {}


def test_ctrl_c_stops_everything_and_keeps_the_record(tmp_path: Path, mission_cli, udp_ports) -> None:  # noqa: ANN001
    """SIGINT to ``python -m gcs.mission`` mid-flight: exit 130, no orphans, events and record on disk."""
    out = tmp_path / "run"
    base = udp_ports(PORT_BLOCK)
    proc = mission_cli(["circle", "--mode", "improved", "--speed", str(CI_SPEED), "--duration", "60", "--out", str(out),
                        "--base-port", str(base), "--gcs-port", str(base + 50), "--no-live"],
                       f"tcp/127.0.0.1:{base + 60}")
    deadline = time.monotonic() + 120.0
    while (time.monotonic() < deadline and proc.poll() is None
           and "flood clock starts" not in _read(out / "events.log")):
        time.sleep(0.2)
    assert proc.poll() is None, f"the mission ended before Ctrl-C: {_read(out / 'events.log')[-3000:]}"
    time.sleep(3.0)
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, f"{stderr}\n{stdout[-2000:]}\n{_read(out / 'events.log')[-3000:]}"
    assert_no_orphans(out)
    assert "interrupted" in _read(out / "events.log")
    record = np.load(out / "record.npz")
    assert len(record["t_s"]) > 5


def test_busy_gcs_port_fails_cleanly(tmp_path: Path, udp_ports) -> None:  # noqa: ANN001
    out = tmp_path / "run"
    options = _options(out, udp_ports(PORT_BLOCK))
    blocker = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)  # the test blocks the very port it chose
    blocker.bind(("127.0.0.1", options.gcs_port))
    try:
        code = run_processes(load_scenario("circle"), options)
    finally:
        blocker.close()
    assert code == 1
    assert str(options.gcs_port) in _read(out / "events.log") and "not free" in _read(out / "events.log")
    assert pids_of_run(out) == {}, "no child may start when the GCS port is taken"


def test_agent_that_cannot_start_stops_the_mission(tmp_path: Path, udp_ports) -> None:  # noqa: ANN001
    out = tmp_path / "run"
    options = _options(out, udp_ports(PORT_BLOCK), extra_agent_args=("--link", "no-such-link"))
    code = run_processes(load_scenario("circle"), options)
    assert code == 1
    assert "failed to start" in _read(out / "events.log")
    assert_no_orphans(out)


@pytest.mark.parametrize(("args", "message"), [
    (["nosuchscenario"], "unknown scenario"),
    (["circle", "--set", "flood.radius_start_m=-3"], "flood.radius_start_m"),
    (["circle", "--set", "novalue"], "expected key=value"),
])
def test_bad_mission_input_is_one_line_and_exit_2(args: list[str], message: str, udp_ports) -> None:  # noqa: ANN001
    base = udp_ports(PORT_BLOCK)
    proc = subprocess.run([sys.executable, "-m", "gcs.mission", *args, "--base-port", str(base),
                           "--gcs-port", str(base + 50)],
                          cwd=REPO, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], proc.stderr


def _mkdir(path: Path) -> Path:
    path.mkdir(parents=True, exist_ok=True)
    return path


def _run(station: GroundStation) -> int:
    return asyncio.run(station.run())


def _read(path: Path) -> str:
    try:
        return path.read_text()
    except OSError:
        return ""


def _event_mission_time(events: str, text: str) -> float:
    """Mission time (the fleet's clock, ``t=...s``) of the first event line holding ``text``."""
    line = next(line for line in events.splitlines() if text in line)
    return float(re.search(r"t=\s*([\d.]+)s", line).group(1))  # type: ignore[union-attr]


def _listen_to_public_keys(hub: str, mission: str, proc: subprocess.Popen[str]) -> tuple[list, dict]:  # noqa: ANN401
    """Join the running mission like an outside Zenoh client and collect its public polygon and state keys."""
    from comms.keys import MissionKeys
    from comms.messages import FloodPolygon, NeighbourState, decode
    from comms.signing import unsigned_body
    from comms.zenoh_session import ZenohConfig, ZenohOpenError, ZenohSession

    keys = MissionKeys(mission)
    polygons: list[FloodPolygon] = []
    states: dict[int, NeighbourState] = {}
    deadline = time.monotonic() + 30.0
    session = None
    while session is None and time.monotonic() < deadline and proc.poll() is None:
        try:
            session = ZenohSession(ZenohConfig.client(hub))
        except ZenohOpenError:
            time.sleep(0.5)
    if session is None:
        return polygons, states
    with session:
        polygon_buf = session.subscribe(keys.polygon)
        state_buf = session.subscribe(keys.all_states)
        while proc.poll() is None:
            time.sleep(0.2)
            for item in polygon_buf.drain():
                polygon = decode(FloodPolygon, item.payload)
                if polygon is not None:
                    polygons.append(polygon)
            for item in state_buf.drain():
                state = decode(NeighbourState, unsigned_body(item.payload))
                if state is not None:
                    states[state.sender_id] = state
    return polygons, states


def _lockstep_summary(duration_s: float) -> dict[str, float]:
    """The reference: the same shortened mission in the lockstep engine on the mock PX4 backend."""
    from gcs.lockstep.backend_choice import BackendKind
    from gcs.lockstep.engine import run_lockstep
    from gcs.metrics.mission import compute_mission_metrics

    scenario = load_scenario("circle")
    result = run_lockstep(scenario, "improved", duration_s=duration_s, backend=BackendKind.PX4)
    return compute_mission_metrics(result.record, result.flood, scenario.camera.fov_deg)["summary"]


def _fly_and_freeze_agent(out: Path, options: ProcessOptions, victim_id: int, frozen_wall_s: float,
                          at_flood_s: float = 6.0) -> tuple[int, GroundStation]:
    """Fly ``options`` and SIGSTOP agent ``victim_id`` for ``frozen_wall_s`` wall seconds once the flood clock passes
    ``at_flood_s``; returns the exit code and the ground station."""
    station = GroundStation(load_scenario("circle"), options, _mkdir(out))
    result: dict[str, int] = {}
    runner = threading.Thread(target=lambda: result.setdefault("code", _run(station)))
    runner.start()
    victim = None
    try:
        deadline = time.monotonic() + 180.0
        while time.monotonic() < deadline and not (station.phase == "mission" and station.flood_time_s() > at_flood_s):
            time.sleep(0.05)
        assert station.phase == "mission", _read(out / "events.log")[-2000:]
        victim = pids_of_run(out)[f"agent_{victim_id}"]
        os.kill(victim, signal.SIGSTOP)
        time.sleep(frozen_wall_s)
        os.kill(victim, signal.SIGCONT)
    finally:
        if victim is not None:
            try:
                os.kill(victim, signal.SIGCONT)
            except ProcessLookupError:
                pass
        runner.join(timeout=300.0)
        if runner.is_alive():
            station.interrupt()
            runner.join(timeout=30.0)
    assert_no_orphans(out)
    return result.get("code", -1), station


def test_paced_clock_waits_for_a_stopped_agent_and_the_mission_is_unchanged(
    tmp_path: Path, udp_ports: Callable[[int], int],
) -> None:
    """SIGSTOP of a boundary agent for 1.2 s (under the 2 s agent timeout): the paced clock holds, nobody is left
    behind, no failsafe fires, and the metrics agree with the lockstep engine's."""
    out = tmp_path / "run"
    options = _options(out, udp_ports(PORT_BLOCK), duration_s=20.0)
    code, station = _fly_and_freeze_agent(out, options, victim_id=3, frozen_wall_s=1.2)
    events = _read(out / "events.log")
    assert code == 0, events[-3000:]
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["engine_health"]["clock"] == "paced" and metrics["engine_health"]["left_behind"] == [], metrics["engine_health"]
    assert metrics["engine_health"]["held_wall_s"] >= 1.0, metrics["engine_health"]
    assert metrics["safety"]["failsafe_count"] == 0 and metrics["safety"]["near_miss_pairs"] == 0, metrics["safety"]
    assert disagreements(_lockstep_summary(20.0), metrics["summary"]) == []
    assert "mission complete | engine" in events or "engine complete" in events


@pytest.mark.slow
def test_free_clock_stopped_agent_meets_px4_offboard_loss(tmp_path: Path, udp_ports) -> None:  # noqa: ANN001
    """The same freeze on a free-running clock: the simulation goes on without the agent and its vehicle leaves
    OFFBOARD after COM_OF_LOSS_T, as PX4 does."""
    out = tmp_path / "run"
    options = _options(out, udp_ports(PORT_BLOCK), duration_s=20.0, clock="free")
    code, station = _fly_and_freeze_agent(out, options, victim_id=3,
                                          frozen_wall_s=2.5)
    events = _read(out / "events.log")
    assert code == 0, events[-3000:]
    metrics = json.loads((out / "metrics.json").read_text())
    assert any(f.startswith("vehicle 3: Failsafe") for f in metrics["safety"]["failsafes"]), metrics["safety"]
    assert re.search(r"vehicle 3: armed, mode (?!OFFBOARD)", events), events[-3000:]


@pytest.mark.slow
def test_paced_clock_leaves_behind_an_agent_silent_past_the_timeout(tmp_path: Path, udp_ports) -> None:  # noqa: ANN001
    """A freeze past ``--agent-timeout-s``: the clock goes on without the agent, its vehicle meets the offboard-loss
    rule in mission time, and the run says so: left behind, engine degraded (``--strict`` exits 1)."""
    out = tmp_path / "run"
    options = _options(out, udp_ports(PORT_BLOCK), duration_s=20.0, agent_timeout_s=1.0, strict=True)
    code, station = _fly_and_freeze_agent(out, options, victim_id=3, frozen_wall_s=4.0)
    events = _read(out / "events.log")
    assert code == 1, events[-3000:]
    assert "agent 3 left behind by the paced clock" in events
    metrics = json.loads((out / "metrics.json").read_text())
    health = metrics["engine_health"]
    assert health["health"] == "degraded" and "3" in health["left_behind"], health
    assert any(f.startswith("vehicle 3: Failsafe") for f in metrics["safety"]["failsafes"]), metrics["safety"]
