"""Fly one vehicle of the mock fleet with MAVSDK: arm, take off, fly offboard velocity, land.

    python -m mock_autopilot --vehicles 1            # terminal 1
    python examples/fly_one_vehicle.py               # terminal 2

The same script flies a PX4 SITL vehicle (``make px4_sitl gz_x500``): MAVSDK cannot tell them apart.
"""

from __future__ import annotations

import argparse
import asyncio
import sys

from mavsdk.asyncio import ComponentType, Configuration, Mavsdk
from mavsdk.asyncio.plugins.action import ActionAsync
from mavsdk.asyncio.plugins.offboard import OffboardAsync, VelocityNedYaw
from mavsdk.asyncio.plugins.telemetry import TelemetryAsync


async def wait_for(read, ok, timeout_s: float = 60.0):  # type: ignore[no-untyped-def]
    """Poll ``await read()`` until ``ok(value)``; returns the value (raises TimeoutError)."""
    async with asyncio.timeout(timeout_s):
        while True:
            value = await read()
            if ok(value):
                return value
            await asyncio.sleep(0.1)


async def fly(url: str, speed_mps: float, seconds: float) -> int:
    config = Configuration.create_with_component_type(ComponentType.COMPANION_COMPUTER)
    async with Mavsdk(config) as mavsdk:
        await mavsdk.add_any_connection(url)
        system = await mavsdk.first_autopilot(timeout_s=10.0)
        if system is None:
            print(f"no autopilot heard on {url}", file=sys.stderr)
            return 1
        telemetry, action, offboard = TelemetryAsync(system), ActionAsync(system), OffboardAsync(system)
        health = await wait_for(telemetry.health, lambda h: h.is_local_position_ok and h.is_armable)
        print("health ok:", health)
        await action.set_takeoff_altitude(5.0)
        await action.arm()
        await action.takeoff()
        pv = await wait_for(telemetry.position_velocity_ned, lambda pv: pv.position.down_m < -4.8)
        print(f"took off: altitude {-pv.position.down_m:.1f} m")
        await offboard.set_velocity_ned(VelocityNedYaw(0.0, 0.0, 0.0, 0.0))
        await offboard.start()
        start = (await telemetry.position_velocity_ned()).position
        await offboard.set_velocity_ned(VelocityNedYaw(speed_mps, 0.0, 0.0, 0.0))
        await asyncio.sleep(seconds)
        await offboard.set_velocity_ned(VelocityNedYaw(0.0, 0.0, 0.0, 0.0))
        await asyncio.sleep(1.0)
        end = (await telemetry.position_velocity_ned()).position
        print(f"offboard: flew {end.north_m - start.north_m:.1f} m north, {end.east_m - start.east_m:.1f} m east")
        await offboard.stop()
        await action.land()
        await wait_for(telemetry.armed, lambda armed: not armed)
        print("landed and disarmed")
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--url", default="udpin://0.0.0.0:14540", help="MAVSDK connection URL")
    parser.add_argument("--speed", type=float, default=2.0, help="north velocity in offboard [m/s]")
    parser.add_argument("--seconds", type=float, default=5.0, help="how long to fly north [s]")
    args = parser.parse_args()
    return asyncio.run(fly(args.url, args.speed, args.seconds))


if __name__ == "__main__":
    sys.exit(main())
