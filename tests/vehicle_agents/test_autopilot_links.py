"""Both autopilot links fly the PX4 offboard recipe against a real mock PX4 over loopback UDP."""

from __future__ import annotations

import asyncio
import time

import pytest

from mock_autopilot.fleet import Fleet
from mock_autopilot.px4_streams import GCS, ONBOARD, STREAM_PROFILES
from mock_autopilot.vehicle import VehicleConfig
from vehicle_agents.autopilot_link import AutopilotLinkError
from vehicle_agents.autopilot_link_mavsdk import TELEMETRY_RATES_HZ, MavsdkAutopilotLink
from vehicle_agents.autopilot_link_pymavlink import PymavlinkAutopilotLink

pytestmark = pytest.mark.integration


async def _until(predicate, timeout_s: float) -> bool:  # noqa: ANN001
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if predicate():
            return True
        await asyncio.sleep(0.05)
    return False


@pytest.mark.parametrize("make_link", [MavsdkAutopilotLink, PymavlinkAutopilotLink])
def test_link_arms_takes_off_and_flies_offboard_velocity(make_link, udp_ports) -> None:  # noqa: ANN001
    port = udp_ports(1)
    async def fly(fleet: Fleet) -> None:
        link = make_link(f"udpin://0.0.0.0:{port}")
        try:
            await link.connect(10.0)
            assert await _until(lambda: link.telemetry.ready_to_arm, 10.0)
            await link.arm()
            await link.takeoff(6.0)
            assert await _until(lambda: -link.telemetry.position_ned_m[2] > 5.4, 20.0), link.telemetry
            await link.start_offboard((0.0, 0.0, 0.0), 0.0)
            assert await _until(lambda: link.telemetry.flight_mode == "OFFBOARD", 5.0), link.telemetry
            start = fleet.truth().position_enu_m[0].copy()
            await link.set_velocity_ned((0.0, 1.0, 0.0), 0.0)  # 1 m/s east
            await asyncio.sleep(2.0)
            moved = fleet.truth().position_enu_m[0] - start
            assert moved[0] > 1.5 and abs(moved[1]) < 0.3, moved  # east in ENU, at speed x2 for 2 s wall
            await link.hold()
            assert await _until(lambda: link.telemetry.flight_mode == "HOLD", 5.0), link.telemetry
        finally:
            await link.close()

    with Fleet([VehicleConfig(0)], base_port=port, gcs_port=port + 5, speed=2.0) as fleet:
        asyncio.run(fly(fleet))


def test_connect_without_autopilot_is_a_clear_error(udp_ports) -> None:  # noqa: ANN001
    port = udp_ports(1)

    async def connect() -> None:
        link = MavsdkAutopilotLink(f"udpin://0.0.0.0:{port}")
        try:
            await link.connect(1.0)
        finally:
            await link.close()

    with pytest.raises(AutopilotLinkError, match="no autopilot heartbeat"):
        asyncio.run(connect())


def test_mavsdk_telemetry_arrives_without_waking_the_event_loop(udp_ports) -> None:  # noqa: ANN001
    port, gcs = udp_ports(1), udp_ports(1)
    """Telemetry is stored on MAVSDK's own callback thread: it stays fresh while the loop is busy, and connecting
    leaves no task behind that the loop would have to run for every MAVLink message."""

    async def watch() -> None:
        link = MavsdkAutopilotLink(f"udpin://0.0.0.0:{port}")
        try:
            tasks_before = len(asyncio.all_tasks())
            await link.connect(10.0)
            assert len(asyncio.all_tasks()) == tasks_before
            assert await _until(lambda: link.telemetry.ready_to_arm, 10.0)
            stamp_s = link.telemetry.last_message_monotonic_s
            time.sleep(1.0)  # the event loop is blocked: nothing of ours runs on it
            assert link.telemetry.last_message_monotonic_s > stamp_s + 0.5
            await link.set_velocity_ned((0.0, 0.0, 0.0), 0.0)  # stored in MAVSDK, no answer to wait for
        finally:
            await link.close()

    with Fleet([VehicleConfig(0)], base_port=port, gcs_port=gcs):
        asyncio.run(watch())


def test_mavsdk_link_asks_px4_for_the_streams_it_reads_and_stops_the_rest(udp_ports) -> None:  # noqa: ANN001
    port, gcs = udp_ports(1), udp_ports(1)
    """Against PX4's own onboard rates, connecting sets them with MAV_CMD_SET_MESSAGE_INTERVAL (MAVSDK set_rate_*)
    on the onboard link only; the ground station's link keeps its rates."""

    async def connect(fleet: Fleet) -> None:
        link = MavsdkAutopilotLink(f"udpin://0.0.0.0:{port}")
        try:
            await link.connect(10.0)
            onboard = fleet.vehicles[0].stream_rates_hz(ONBOARD)
            assert onboard["LOCAL_POSITION_NED"] == pytest.approx(TELEMETRY_RATES_HZ["position_velocity_ned"])
            assert onboard["ATTITUDE"] == pytest.approx(TELEMETRY_RATES_HZ["attitude_euler"])
            assert onboard["GLOBAL_POSITION_INT"] == pytest.approx(TELEMETRY_RATES_HZ["position"])
            assert "ALTITUDE" not in onboard and "VFR_HUD" not in onboard
            assert fleet.vehicles[0].stream_rates_hz(GCS) == pytest.approx(STREAM_PROFILES["px4"][GCS])
        finally:
            await link.close()

    with Fleet([VehicleConfig(0, stream_profile="px4")], base_port=port, gcs_port=gcs) as fleet:
        asyncio.run(connect(fleet))
