"""How many vehicles one fleet process holds at real time, per stream-rate profile, and the CPU per vehicle.

Method: start a Fleet of N GPS vehicles (speed 1) whose links send to UDP sink sockets (bound, never read:
the kernel drops what overflows, so the sink costs no CPU); arm them and take them off to 5 m with MAVLink
commands (``--idle`` leaves them on the ground); after a 2 s warm-up, measure over ``--seconds``:
* telemetry messages actually sent per vehicle per second vs what the profile asks for (a vehicle without an
  offboard setpoint sends every stream of the profile except POSITION_TARGET_LOCAL_NED);
* CPU of the whole process (``time.process_time``; the measuring thread sleeps) per wall second, and per vehicle;
* fleet ticks that overran their 10 ms period.
"Holds real time" = at least 95 % of the asked telemetry rate is delivered and the process uses less than 95 % of
one core (Python's GIL: one fleet process is one core). The ladder stops after the first N that does not hold.
On a shared machine the direct answer depends on how much CPU the other jobs leave us, so every row also gives
the load average and the CPU-bound estimate 0.95 core / (CPU per vehicle), what one free core would hold.
Run from the repository root: ``.venv/bin/python -m bench.autopilot_capacity [--profiles px4 reduced]``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import socket
import time

from pymavlink.dialects.v20 import common as mavlink

from mock_autopilot.fleet import Fleet
from mock_autopilot.px4_streams import STREAM_PROFILES
from mock_autopilot.vehicle import VehicleConfig


def asked_rate_hz(profile: str) -> float:
    """Datagrams per second an idle GPS vehicle should send on both links."""
    return sum(hz for link in STREAM_PROFILES[profile].values() for name, hz in link.items() if name != "POSITION_TARGET_LOCAL_NED")


def take_off_all(fleet: Fleet) -> None:
    """Arm every vehicle and send it to 5 m with real MAVLink commands, as a ground station would."""
    client = mavlink.MAVLink(None, 255, 190)
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    nan = math.nan
    for i, vehicle in enumerate(fleet.vehicles):
        target = fleet.ports(i).onboard_local
        for command, params in ((400, (1, 0, 0, 0, 0, 0, 0)), (22, (nan, nan, nan, nan, nan, nan, nan))):
            msg = mavlink.MAVLink_command_long_message(vehicle.system_id, 1, command, 0, *params)
            sock.sendto(msg.pack(client), target)
        if i % 50 == 49:
            time.sleep(0.05)
    sock.close()
    deadline = time.monotonic() + 20.0
    while time.monotonic() < deadline and not (fleet.truth().position_enu_m[:, 2] > 4.5).all():
        time.sleep(0.2)


def measure(n: int, profile: str, seconds: float, base_port: int, flying: bool) -> dict[str, float | int | str | bool]:
    sinks = []
    for port in [base_port + i for i in range(n)] + [base_port + 990]:
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        s.bind(("127.0.0.1", port))
        sinks.append(s)
    configs = [VehicleConfig(i, stream_profile=profile, pad_enu_m=(i * 2.0, 0.0, 0.0)) for i in range(n)]
    try:
        with Fleet(configs, base_port=base_port, gcs_port=base_port + 990, speed=1.0) as fleet:
            if flying:
                take_off_all(fleet)
            time.sleep(2.0)

            def sent() -> int:
                return sum(link.sent_messages for links in fleet.links for link in links.values())

            s0, c0, w0, t0, o0 = sent(), time.process_time(), time.monotonic(), fleet.ticks, fleet.tick_overruns
            time.sleep(seconds)
            s1, c1, w1, t1, o1 = sent(), time.process_time(), time.monotonic(), fleet.ticks, fleet.tick_overruns
    finally:
        for s in sinks:
            s.close()
    wall = w1 - w0
    delivered = (s1 - s0) / wall / n
    asked = asked_rate_hz(profile)
    cpu = (c1 - c0) / wall
    holds = delivered >= 0.95 * asked and cpu < 0.95
    return {
        "profile": profile, "vehicles": n, "flying": flying, "asked_hz_per_vehicle": round(asked, 1),
        "delivered_hz_per_vehicle": round(delivered, 1), "delivered_ratio": round(delivered / asked, 3),
        "cpu_cores": round(cpu, 3), "cpu_ms_per_vehicle_s": round(1000 * cpu / n, 3),
        "tick_overrun_ratio": round((o1 - o0) / max(1, t1 - t0), 3), "holds_real_time": holds,
        "one_core_estimate_vehicles": int(0.95 / (cpu / n)) if cpu > 0 else None,
        "load_average_1min": round(os.getloadavg()[0], 1),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profiles", nargs="+", default=["px4", "reduced"], choices=sorted(STREAM_PROFILES))
    parser.add_argument("--ladder", type=int, nargs="+", default=[10, 25, 50, 75, 100, 150, 200, 300, 400, 600, 800])
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--base-port", type=int, default=22000)
    parser.add_argument("--idle", action="store_true", help="leave the vehicles disarmed on the ground")
    args = parser.parse_args()
    for profile in args.profiles:
        for n in args.ladder:
            result = measure(n, profile, args.seconds, args.base_port, not args.idle)
            print(json.dumps(result), flush=True)
            if not result["holds_real_time"]:
                break


if __name__ == "__main__":
    main()
