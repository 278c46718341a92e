"""The simulator bridge over real Zenoh sessions: truth, camera frames, and the flood clock from the GCS command."""

from __future__ import annotations

import time

import numpy as np
import pytest

from comms.keys import MissionKeys
from comms.messages import CameraFrame, GroundTruth, MissionCommand, decode, encode
from comms.zenoh_session import ZenohConfig, ZenohSession
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.sim_bridge.bridge import CameraStreamer, SimBridge, VehicleTruth
from mock_autopilot.world.flood_model import ExpandingCircle

pytestmark = pytest.mark.integration


def _vehicle(vid: int, east: float, up: float) -> VehicleTruth:
    return VehicleTruth(vid, np.array([east, 0.0, up]), np.zeros(3), 0.0)


def _drain_until(buf, predicate, timeout_s: float = 5.0):  # noqa: ANN001, ANN202
    deadline = time.monotonic() + timeout_s
    got = []
    while time.monotonic() < deadline:
        got.extend(buf.drain())
        if predicate(got):
            return got
        time.sleep(0.02)
    return got


def test_bridge_publishes_truth_frames_and_follows_flood_clock(zenoh_endpoint) -> None:  # noqa: ANN001
    hub_ep = zenoh_endpoint()
    keys = MissionKeys("bridgetest")
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub, ZenohSession(ZenohConfig.member(hub_ep)) as sim:
        truth_buf = hub.subscribe(keys.truth)
        cam_buf = hub.subscribe(keys.all_cameras)
        time.sleep(0.5)
        cameras = CameraStreamer(sim, "bridgetest", ExpandingCircle(), CameraModel(), seed=1, camera_period_s=0.1)
        bridge = SimBridge(sim, "bridgetest", truth_period_s=0.05, cameras=cameras)
        vehicles = [_vehicle(1, 12.0, 10.0), _vehicle(2, 14.0, 0.0)]
        bridge.tick(0.0, vehicles)
        got = _drain_until(cam_buf, lambda g: len(g) >= 1)
        frames = [decode(CameraFrame, r.payload) for r in got]
        assert [f.vehicle_id for f in frames] == [1], "only the airborne vehicle gets frames"
        image = np.frombuffer(frames[0].image, np.uint8).reshape(128, 128, 3)
        assert image.std() > 5.0
        truth = decode(GroundTruth, _drain_until(truth_buf, lambda g: len(g) >= 1)[-1].payload)
        assert truth.vehicle_ids == [1, 2] and truth.positions_enu_m[0] == (12.0, 0.0, 10.0)

        assert cameras.flood_time_s(5.0) == 0.0
        hub.put(keys.command, encode(MissionCommand(seq=1, t_s=3.0, command="start", flood_clock_start_t_s=3.0)))
        deadline = time.monotonic() + 5.0
        while cameras.flood_clock_start_s is None and time.monotonic() < deadline:
            bridge.tick(4.0, vehicles)
            time.sleep(0.05)
        assert cameras.flood_clock_start_s == 3.0
        assert cameras.flood_time_s(10.0) == pytest.approx(7.0)


def test_only_camera_users_get_frames(zenoh_endpoint) -> None:  # noqa: ANN001
    hub_ep = zenoh_endpoint()
    from mock_autopilot.sim_bridge.bridge import camera_users

    roles = {1: "boundary", 2: "leader", 3: "follower", 4: "boundary"}
    assert camera_users(roles) == {1, 4}
    assert camera_users(roles, "all") is None
    keys = MissionKeys("bridgecams")
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub, ZenohSession(ZenohConfig.member(hub_ep)) as sim:
        cam_buf = hub.subscribe(keys.all_cameras)
        time.sleep(0.5)
        cameras = CameraStreamer(sim, "bridgecams", ExpandingCircle(), CameraModel(), seed=1, camera_period_s=0.1,
                                 camera_vehicle_ids={1})
        cameras.stream(0.0, [_vehicle(1, 12.0, 10.0), _vehicle(2, 0.0, 10.0)])
        got = _drain_until(cam_buf, lambda g: len(g) >= 1)
        time.sleep(0.3)
        got += cam_buf.drain()
        assert sorted(decode(CameraFrame, r.payload).vehicle_id for r in got) == [1]


def test_camera_process_renders_from_published_truth(tmp_path, zenoh_endpoint) -> None:  # noqa: ANN001
    """``python -m mock_autopilot.sim_bridge.cameras`` turns the fleet's published truth into camera frames."""
    import subprocess
    import sys

    from comms.messages import encode as encode_msg
    from mock_autopilot.sim_bridge.bridge import ground_truth_message

    keys = MissionKeys("camproc")
    hub_ep = zenoh_endpoint()
    with ZenohSession(ZenohConfig.hub(hub_ep)) as hub:
        cam_buf = hub.subscribe(keys.all_cameras)
        log = (tmp_path / "cameras.log").open("wb")
        proc = subprocess.Popen([sys.executable, "-m", "mock_autopilot.sim_bridge.cameras", "--mission", "camproc",
                                 "--connect", hub_ep], stdout=log, stderr=subprocess.STDOUT)
        try:
            deadline = time.monotonic() + 20.0
            t_s = 0.0
            frames = []
            while time.monotonic() < deadline and len(frames) < 3:
                truth = ground_truth_message(t_s, [_vehicle(1, 12.0, 10.0), _vehicle(9, 0.0, 10.0)])
                hub.put(keys.truth, encode_msg(truth))
                t_s += 0.1
                time.sleep(0.1)
                frames += [decode(CameraFrame, r.payload) for r in cam_buf.drain()]
        finally:
            proc.terminate()
            proc.wait(timeout=10)
        assert len(frames) >= 3, (tmp_path / "cameras.log").read_text()
        assert {f.vehicle_id for f in frames} == {1}, "circle's vehicle 9 is the leader: no camera stream"
        assert proc.returncode == 0
