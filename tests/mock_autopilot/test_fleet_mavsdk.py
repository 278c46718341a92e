"""Fleet with MAVSDK 4.x (the C++ library through ctypes) as the client (ports from the ``udp_ports`` fixture).

MAVSDK listens with ``udpin://0.0.0.0:PORT`` and the vehicle sends there first, as PX4 SITL does.
Simulated time runs 4x faster than the wall clock (``speed=4``): MAVSDK's 20 Hz offboard stream is then 5 Hz
in simulated time, still well inside COM_OF_LOSS_T.
"""

import asyncio
import math
from typing import Any, Awaitable, Callable

import pytest
from mavsdk.asyncio import ComponentType, Configuration, Mavsdk
from mavsdk.asyncio.plugins.action import ActionAsync
from mavsdk.asyncio.plugins.offboard import OffboardAsync, VelocityNedYaw
from mavsdk.asyncio.plugins.param import ParamAsync
from mavsdk.asyncio.plugins.telemetry import TelemetryAsync

from mock_autopilot.fleet import Fleet
from mock_autopilot.vehicle import VehicleConfig

pytestmark = pytest.mark.integration
SPEED = 4.0


async def wait_for(read: Callable[[], Awaitable[Any]], ok: Callable[[Any], bool], timeout_s: float = 20.0) -> Any:
    async with asyncio.timeout(timeout_s):
        while True:
            value = await read()
            if ok(value):
                return value
            await asyncio.sleep(0.05)


async def wait_truth(fleet: Fleet, ok: Callable[[Any], bool], timeout_s: float = 20.0) -> Any:
    return await wait_for(lambda: asyncio.sleep(0, fleet.truth()), ok, timeout_s)


async def connect(port: int) -> tuple[Mavsdk, Any]:
    mavsdk = Mavsdk(Configuration.create_with_component_type(ComponentType.COMPANION_COMPUTER))
    await mavsdk.add_any_connection(f"udpin://0.0.0.0:{port}")
    system = await mavsdk.first_autopilot(timeout_s=10.0)
    assert system is not None
    return mavsdk, system


def test_mavsdk_full_flight(udp_ports: Callable[[int], int]) -> None:
    base, gcs = udp_ports(1), udp_ports(1)

    async def scenario() -> None:
        with Fleet([VehicleConfig(0, pad_enu_m=(14.0, 0.0, 0.0))], base_port=base, gcs_port=gcs, speed=SPEED) as fleet:
            mavsdk, system = await connect(base)
            try:
                telemetry, action, offboard = TelemetryAsync(system), ActionAsync(system), OffboardAsync(system)
                health = await wait_for(telemetry.health, lambda h: h.is_home_position_ok and h.is_global_position_ok)
                assert health.is_local_position_ok and health.is_armable
                assert health.is_gyrometer_calibration_ok and health.is_accelerometer_calibration_ok
                await action.set_takeoff_altitude(6.0)
                assert fleet.vehicles[0].params["MIS_TAKEOFF_ALT"] == 6.0
                assert await action.get_takeoff_altitude() == pytest.approx(6.0)
                await action.arm()
                await action.takeoff()
                pv = await wait_for(telemetry.position_velocity_ned, lambda pv: pv.position.down_m < -5.8)
                assert abs(pv.position.north_m) < 0.2
                await wait_truth(fleet, lambda t: t.modes[0] == "AUTO.LOITER")
                await offboard.set_velocity_ned(VelocityNedYaw(0.0, 0.0, 0.0, 0.0))
                await offboard.start()
                assert fleet.truth().modes[0] == "OFFBOARD"
                start = fleet.truth()
                await offboard.set_velocity_ned(VelocityNedYaw(-1.0, 2.0, 0.0, 90.0))
                t0 = fleet.clock.now_s()
                await asyncio.sleep(5.0 / SPEED)
                await offboard.set_velocity_ned(VelocityNedYaw(0.0, 0.0, 0.0, 90.0))
                elapsed = fleet.clock.now_s() - t0
                await asyncio.sleep(1.5 / SPEED)
                end = fleet.truth()
                moved_enu = end.position_enu_m[0] - start.position_enu_m[0]
                # NED (-1 north, +2 east) for ~5 s simulated -> ENU (+2 east, -1 north)
                assert moved_enu[0] == pytest.approx(2.0 * elapsed, rel=0.15)
                assert moved_enu[1] == pytest.approx(-1.0 * elapsed, rel=0.15)
                assert abs(moved_enu[2]) < 0.3
                assert end.yaw_ned_rad[0] == pytest.approx(math.pi / 2, abs=0.05)
                await offboard.stop()
                await action.land()
                await wait_for(telemetry.in_air, lambda in_air: not in_air, timeout_s=30)
                await wait_for(telemetry.armed, lambda armed: not armed, timeout_s=10)
                texts = [t for t in fleet.vehicles[0].rejections]
                assert texts == [] or all(not t.startswith("setpoint") for t in texts)
            finally:
                mavsdk.destroy()

    asyncio.run(scenario())


def test_mavsdk_offboard_loss_fallback_and_no_gps_vehicle_and_two_vehicles_with_signing_key(
    udp_ports: Callable[[int], int],
) -> None:
    base, gcs = udp_ports(2), udp_ports(1)

    async def scenario() -> None:
        configs = [VehicleConfig(0), VehicleConfig(1, has_gps=False, pad_enu_m=(1.5, 0.0, 0.0))]
        # with a signing key the GCS link requires signatures; the onboard link, where MAVSDK talks, stays unsigned
        with Fleet(configs, base_port=base, gcs_port=gcs, speed=SPEED, signing_key=bytes(range(32))) as fleet:
            clients = [await connect(base), await connect(base + 1)]
            try:
                (m0, s0), (m1, s1) = clients
                assert await s0.get_system_id() == 1 and await s1.get_system_id() == 2
                health = await wait_for(TelemetryAsync(s1).health, lambda h: h.is_local_position_ok and h.is_armable)
                assert not health.is_global_position_ok and not health.is_home_position_ok
                offboards = [OffboardAsync(s0), OffboardAsync(s1)]  # a plugin that is garbage-collected stops its stream
                for system, index in ((s0, 0), (s1, 1)):
                    param = ParamAsync(system)
                    await param.set_param_int("COM_OBL_RC_ACT", 4)
                    await param.set_param_float("COM_OF_LOSS_T", 2.0)
                    assert await param.get_param_int("COM_OBL_RC_ACT") == 4
                    assert fleet.vehicles[index].params["COM_OBL_RC_ACT"] == 4
                    offboard = offboards[index]
                    await offboard.set_velocity_ned(VelocityNedYaw(0.0, 0.0, 0.0, 0.0))
                    await offboard.start()
                    await ActionAsync(system).arm()
                    await offboard.set_velocity_ned(VelocityNedYaw(0.0, 0.0, -2.0, 0.0))
                truth = await wait_truth(fleet, lambda t: (t.position_enu_m[:, 2] > 4.0).all())
                assert truth.modes == ("OFFBOARD", "OFFBOARD")
                # the no-GPS vehicle's agent dies: its stream stops, PX4 lands it after COM_OF_LOSS_T
                m1.destroy()
                t_stop = fleet.clock.now_s()
                truth = await wait_truth(fleet, lambda t: t.modes[1] == "AUTO.LAND")
                assert fleet.clock.now_s() - t_stop == pytest.approx(2.0, abs=0.6)
                assert truth.modes[0] == "OFFBOARD"
                await wait_truth(fleet, lambda t: not t.armed[1], timeout_s=30)
                assert fleet.truth().position_enu_m[1][2] == pytest.approx(0.0, abs=0.05)
                await offboards[0].set_velocity_ned(VelocityNedYaw(0.0, 0.0, 0.0, 0.0))
                await offboards[0].stop()
                assert fleet.truth().modes[0] == "AUTO.LOITER"
            finally:
                clients[0][0].destroy()

    asyncio.run(scenario())


def test_mavsdk_goto_hold_and_return_to_launch(udp_ports: Callable[[int], int]) -> None:
    base, gcs = udp_ports(1), udp_ports(1)

    async def scenario() -> None:
        with Fleet([VehicleConfig(0, pad_enu_m=(5.0, 5.0, 0.0))], base_port=base, gcs_port=gcs, speed=SPEED) as fleet:
            mavsdk, system = await connect(base)
            try:
                telemetry, action = TelemetryAsync(system), ActionAsync(system)
                await wait_for(telemetry.health, lambda h: h.is_home_position_ok and h.is_armable)
                await action.set_return_to_launch_altitude(8.0)
                assert fleet.vehicles[0].params["RTL_RETURN_ALT"] == 8.0
                await action.set_takeoff_altitude(4.0)
                await action.arm()
                await action.takeoff()
                await wait_truth(fleet, lambda t: t.modes[0] == "AUTO.LOITER" and t.position_enu_m[0][2] > 3.8)
                home = await telemetry.home()
                position = await telemetry.position()
                # 10 m north of the pad: 1 deg of latitude is ~111.2 km on the projection's sphere
                await action.goto_location(position.latitude_deg + 10.0 / 111_195.0, position.longitude_deg,
                                           position.absolute_altitude_m + 2.0, 0.0)
                truth = await wait_truth(fleet, lambda t: abs(t.position_enu_m[0][1] - 15.0) < 0.3 and abs(t.velocity_enu_mps[0][1]) < 0.1)
                assert truth.position_enu_m[0] == pytest.approx([5.0, 15.0, 6.0], abs=0.4)
                await action.hold()
                await action.return_to_launch()
                await wait_truth(fleet, lambda t: t.modes[0] == "AUTO.RTL")
                await wait_truth(fleet, lambda t: t.position_enu_m[0][2] > 7.7)  # climbs to RTL_RETURN_ALT first
                await wait_for(telemetry.armed, lambda armed: not armed, timeout_s=40)
                truth = fleet.truth()
                assert truth.position_enu_m[0] == pytest.approx([5.0, 5.0, 0.0], abs=0.6)
                assert home.relative_altitude_m == pytest.approx(0.0, abs=0.1)
            finally:
                mavsdk.destroy()

    asyncio.run(scenario())
