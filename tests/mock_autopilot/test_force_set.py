"""FORCE_SET (type_mask bit 9) over real UDP, as PX4's receiver treats it: refused only with an acceleration in use.

A velocity-only setpoint stream enters OFFBOARD with and without bit 9, with pymavlink as the only client and with
MAVSDK arming and watching the flight mode while pymavlink streams the setpoints on the GCS link (MAVSDK's own
offboard plugin never sets bit 9, and its stream would be proof of life on its own). An acceleration setpoint
with bit 9 is refused with PX4's STATUSTEXT and is no proof of life, so OFFBOARD is refused.
"""

from __future__ import annotations

import asyncio
import os
import threading
import time
from collections.abc import Callable, Iterator

import pytest

os.environ.setdefault("MAVLINK20", "1")
from mavsdk.asyncio import ComponentType, Configuration, Mavsdk  # noqa: E402
from mavsdk.asyncio.plugins.action import ActionAsync  # noqa: E402
from mavsdk.asyncio.plugins.telemetry import FlightMode, TelemetryAsync  # noqa: E402
from pymavlink import mavutil  # noqa: E402

from comms.px4 import MODE_TABLE, MavResult, Px4Mode, mode_name  # noqa: E402
from mock_autopilot.fleet import Fleet  # noqa: E402
from mock_autopilot.setpoints import FORCE_SET, MASK_VELOCITY_AND_YAW  # noqa: E402
from mock_autopilot.vehicle import VehicleConfig  # noqa: E402

pytestmark = pytest.mark.integration
ACCELERATION_ONLY = 0b1100_0011_1111  # positions, velocities, yaw, yaw rate ignored
ml = mavutil.mavlink
OFFBOARD = MODE_TABLE[Px4Mode.OFFBOARD]


def connect(port: int) -> mavutil.mavfile:
    m = mavutil.mavlink_connection(f"udpin:127.0.0.1:{port}", source_system=255, source_component=190)
    assert m.wait_heartbeat(timeout=5) is not None, f"no heartbeat on {port}"
    return m


def wait_msg(m: mavutil.mavfile, kind: str, ok: Callable[[object], bool], timeout_s: float = 5.0) -> object | None:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        msg = m.recv_match(type=kind, blocking=True, timeout=0.2)
        if msg is not None and ok(msg):
            return msg
    return None


def command(m: mavutil.mavfile, cmd: int, *params: float) -> int | None:
    p = list(params) + [0.0] * (7 - len(params))
    m.mav.command_long_send(1, 1, cmd, 0, *p)
    reply = wait_msg(m, "COMMAND_ACK", lambda a: a.command == cmd, 3.0)
    return None if reply is None else reply.result


@pytest.fixture
def setpoint_stream() -> Iterator[Callable[[mavutil.mavfile, int], None]]:
    """Start streaming a velocity (or acceleration) setpoint at 20 Hz with a given type_mask; stopped at teardown."""
    stop = threading.Event()
    threads: list[threading.Thread] = []

    def start(m: mavutil.mavfile, type_mask: int) -> None:
        def run() -> None:
            while not stop.is_set():
                m.mav.set_position_target_local_ned_send(0, 1, 1, ml.MAV_FRAME_LOCAL_NED, type_mask,
                                                         0, 0, 0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.1, 0.0, 0.0)
                time.sleep(0.05)

        threads.append(threading.Thread(target=run, daemon=True))
        threads[-1].start()

    yield start
    stop.set()
    for t in threads:
        t.join(timeout=2.0)


@pytest.mark.parametrize("type_mask", [MASK_VELOCITY_AND_YAW, MASK_VELOCITY_AND_YAW | FORCE_SET])
def test_pymavlink_velocity_setpoints_enter_offboard_with_and_without_bit_9(
    type_mask: int, udp_ports: Callable[[int], int], setpoint_stream: Callable[[mavutil.mavfile, int], None],
) -> None:
    base, gcs = udp_ports(1), udp_ports(1)
    with Fleet([VehicleConfig(0)], base_port=base, gcs_port=gcs, speed=2.0) as fleet:
        m = connect(base)
        setpoint_stream(m, type_mask)
        time.sleep(0.3)
        assert command(m, ml.MAV_CMD_COMPONENT_ARM_DISARM, 1) == MavResult.ACCEPTED
        assert command(m, ml.MAV_CMD_DO_SET_MODE, ml.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, OFFBOARD.main_mode) == MavResult.ACCEPTED
        assert wait_msg(m, "HEARTBEAT", lambda h: mode_name(h.custom_mode) == "OFFBOARD") is not None
        assert fleet.vehicles[0].offboard_setpoint.type_mask == type_mask
        assert not any(k.startswith("setpoint_") for k in fleet.vehicles[0].rejections)


def test_pymavlink_acceleration_with_bit_9_is_refused_and_logged(
    udp_ports: Callable[[int], int], setpoint_stream: Callable[[mavutil.mavfile, int], None],
) -> None:
    base, gcs = udp_ports(1), udp_ports(1)
    with Fleet([VehicleConfig(0)], base_port=base, gcs_port=gcs, speed=2.0) as fleet:
        m = connect(base)
        setpoint_stream(m, ACCELERATION_ONLY | FORCE_SET)
        text = wait_msg(m, "STATUSTEXT", lambda t: "force not supported" in t.text)
        assert text is not None and text.severity == ml.MAV_SEVERITY_CRITICAL
        assert command(m, ml.MAV_CMD_COMPONENT_ARM_DISARM, 1) == MavResult.ACCEPTED
        result = command(m, ml.MAV_CMD_DO_SET_MODE, ml.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, OFFBOARD.main_mode)
        assert result == MavResult.TEMPORARILY_REJECTED
        assert fleet.truth().modes[0] == "AUTO.LOITER"
        assert fleet.vehicles[0].rejections["setpoint_force_setpoint_unsupported"] > 0
        assert fleet.vehicles[0].offboard_setpoint is None


async def _mavsdk_scenario(base: int, gcs: int, type_mask: int) -> tuple[FlightMode, str]:
    """MAVSDK arms and watches the flight mode; pymavlink on the GCS link streams setpoints and asks for OFFBOARD."""
    with Fleet([VehicleConfig(0)], base_port=base, gcs_port=gcs, speed=2.0):
        mavsdk = Mavsdk(Configuration.create_with_component_type(ComponentType.COMPANION_COMPUTER))
        await mavsdk.add_any_connection(f"udpin://0.0.0.0:{base}")
        system = await mavsdk.first_autopilot(timeout_s=10.0)
        assert system is not None
        try:
            telemetry, action = TelemetryAsync(system), ActionAsync(system)
            async with asyncio.timeout(15.0):
                while not (await telemetry.health()).is_armable:
                    await asyncio.sleep(0.1)
            m = await asyncio.to_thread(connect, gcs)
            stop = threading.Event()

            def stream() -> None:
                while not stop.is_set():
                    m.mav.set_position_target_local_ned_send(0, 1, 1, ml.MAV_FRAME_LOCAL_NED, type_mask, 0, 0, 0,
                                                             0.0, 0.0, 0.0, 0.0, 0.0, -0.1, 0.0, 0.0)
                    time.sleep(0.05)

            streamer = threading.Thread(target=stream, daemon=True)
            streamer.start()
            try:
                await asyncio.sleep(0.3)
                await action.arm()
                await asyncio.to_thread(command, m, ml.MAV_CMD_DO_SET_MODE, ml.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED,
                                        OFFBOARD.main_mode)
                await asyncio.sleep(0.5)
                mode = await telemetry.flight_mode()
                text = (await asyncio.wait_for(telemetry.status_text(), 5.0)).text
            finally:
                stop.set()
                streamer.join(timeout=2.0)
            return mode, text
        finally:
            del mavsdk


@pytest.mark.parametrize("type_mask", [MASK_VELOCITY_AND_YAW, MASK_VELOCITY_AND_YAW | FORCE_SET])
def test_mavsdk_sees_offboard_with_velocity_setpoints_with_and_without_bit_9(
    type_mask: int, udp_ports: Callable[[int], int],
) -> None:
    mode, _ = asyncio.run(_mavsdk_scenario(udp_ports(1), udp_ports(1), type_mask))
    assert mode == FlightMode.OFFBOARD


def test_mavsdk_sees_acceleration_with_bit_9_refused(udp_ports: Callable[[int], int]) -> None:
    mode, text = asyncio.run(_mavsdk_scenario(udp_ports(1), udp_ports(1), ACCELERATION_ONLY | FORCE_SET))
    assert mode == FlightMode.HOLD
    assert "force not supported" in text
