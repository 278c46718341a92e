"""The relative-position sensor over real Zenoh sessions: the camera process's streamer publishes each GPS-less
drone's measurement on its grid, and the agent's swarm link hands the newest one to the core."""

from __future__ import annotations

import time

import numpy as np
import pytest

from comms.signing import KEY_BYTES, MissionKey
from comms.zenoh_session import ZenohConfig, ZenohSession
from mission_plan.weather import SensorSpec
from mock_autopilot.sim_bridge.bridge import VehicleTruth
from mock_autopilot.sim_bridge.ranging_streamer import RangingStreamer
from vehicle_agents.swarm_link_zenoh import ZenohSwarmLink

pytestmark = pytest.mark.integration

DRIFTING = SensorSpec(odometry_drift_frac=0.01, ranging_sigma_m=0.0)


def _vehicles(t_s: float) -> list[VehicleTruth]:
    return [VehicleTruth(1, np.array([0.0, 0.0, 10.0]), np.zeros(3), 0.0),
            VehicleTruth(2, np.array([t_s, 8.0, 10.0]), np.zeros(3), 0.0),
            VehicleTruth(3, np.array([40.0, 0.0, 10.0]), np.zeros(3), 0.0)]


def test_the_agent_gets_its_newest_measurement_of_the_neighbours_in_range(zenoh_endpoint) -> None:  # noqa: ANN001
    hub_ep = zenoh_endpoint()
    key = MissionKey(bytes(range(KEY_BYTES)))
    with ZenohSession(ZenohConfig.hub(hub_ep)) as sim:
        streamer = RangingStreamer(sim, "rangingtest", DRIFTING, seed=1, carrier_ids=[1, 3])
        silent = RangingStreamer(sim, "rangingtest", SensorSpec(), seed=1, carrier_ids=[1, 3])
        agent = ZenohSwarmLink(1, "rangingtest", ZenohConfig.member(hub_ep), via_radio=True, key=key, ranges=True)
        try:
            time.sleep(0.5)
            silent.stream(0.0, _vehicles(0.0))
            assert silent.sent == 0, "no drone reads the sensor while odometry does not drift"
            deadline = time.monotonic() + 5.0
            t_s = 0.0
            while time.monotonic() < deadline:
                streamer.stream(t_s, _vehicles(t_s))
                msg = agent.latest_ranging()
                if msg is not None and msg.t_s >= 0.3:
                    break
                t_s += 0.05
                time.sleep(0.05)
            assert msg is not None and msg.vehicle_id == 1
            assert msg.neighbour_ids == [2]
            # Facing north (yaw 0): the neighbour 8 m north and t_s east is ahead and to the right.
            assert np.allclose(msg.forward_right_m, [(8.0, msg.t_s)])
            assert streamer.sent >= 2 * 4, "both carriers, at 10 Hz of mission time"
        finally:
            agent.close()
