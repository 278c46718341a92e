"""Latency of SET_POSITION_TARGET_LOCAL_NED: UDP datagram sent -> vehicle applies it (p50/p99), on loopback.

Two instants are timed for every setpoint (each carries a unique vx so it can be recognised):
* "accepted": the vehicle's ``handle`` has stored it as the offboard setpoint (socket -> parse -> checks -> state);
* "flown": the end of the first physics tick that flies it (adds the wait for the fleet's next 10 ms tick).
The timing wrappers are installed by this script on the running fleet's vehicle objects; production code is
unchanged. Run from the repository root: ``.venv/bin/python -m bench.autopilot_latency [--samples 1000] [--vehicles 1 50]``.
"""

from __future__ import annotations

import argparse
import json
import math
import socket
import time

import numpy as np
from pymavlink.dialects.v20 import common as mavlink

from comms.px4 import Px4Mode
from mock_autopilot.fleet import Fleet


def measure(samples: int, vehicles: int, rate_hz: float, base_port: int) -> dict[str, float]:
    accepted: dict[int, float] = {}
    flown: dict[int, float] = {}
    with Fleet(vehicles, base_port=base_port, gcs_port=base_port + 900, speed=1.0) as fleet:
        vehicle = fleet.vehicles[0]
        original_handle, original_tick = vehicle.handle, vehicle.tick
        last_key = [-1]

        def timed_handle(link, msg, now_s):  # type: ignore[no-untyped-def]
            out = original_handle(link, msg, now_s)
            if msg.get_type() == "SET_POSITION_TARGET_LOCAL_NED":
                accepted[int(round(msg.vx * 1e4))] = time.perf_counter()
            return out

        def timed_tick(now_s):  # type: ignore[no-untyped-def]
            out = original_tick(now_s)
            sp = vehicle.offboard_setpoint
            if sp is not None and vehicle.mode is Px4Mode.OFFBOARD:
                key = int(round(sp.velocity_ned_mps[0] * 1e4))
                if key != last_key[0]:
                    last_key[0] = key
                    flown.setdefault(key, time.perf_counter())
            return out

        vehicle.handle, vehicle.tick = timed_handle, timed_tick  # type: ignore[method-assign]
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        sock.bind(("127.0.0.1", base_port))
        target = fleet.ports(0).onboard_local
        client = mavlink.MAVLink(None, 1, 191)

        def frame(vx: float) -> bytes:
            msg = mavlink.MAVLink_set_position_target_local_ned_message(
                0, 1, 1, 1, 2503, math.nan, math.nan, math.nan, vx, 0.0, 0.0, math.nan, math.nan, math.nan, 0.0, math.nan)
            data = msg.pack(client)
            client.seq = (client.seq + 1) % 256
            return data

        sock.sendto(frame(0.0), target)
        time.sleep(0.05)
        sock.sendto(mavlink.MAVLink_command_long_message(1, 1, 176, 0, 1, 6, 0, 0, 0, 0, 0).pack(client), target)
        sock.sendto(mavlink.MAVLink_command_long_message(1, 1, 400, 0, 1, 0, 0, 0, 0, 0, 0).pack(client), target)
        time.sleep(0.2)
        assert vehicle.mode is Px4Mode.OFFBOARD and vehicle.armed, vehicle.mode
        sent: dict[int, float] = {}
        period = 1.0 / rate_hz
        next_t = time.perf_counter()
        for i in range(1, samples + 1):
            key = i
            sent[key] = time.perf_counter()
            sock.sendto(frame(key * 1e-4), target)
            next_t += period
            time.sleep(max(0.0, next_t - time.perf_counter()))
        time.sleep(0.2)
        sock.close()
    acc = np.array([accepted[k] - sent[k] for k in sent if k in accepted]) * 1e3
    fl = np.array([flown[k] - sent[k] for k in sent if k in flown]) * 1e3
    return {
        "vehicles": vehicles,
        "samples": samples,
        "accepted_count": int(acc.size),
        "accepted_p50_ms": float(np.percentile(acc, 50)),
        "accepted_p99_ms": float(np.percentile(acc, 99)),
        "flown_count": int(fl.size),
        "flown_p50_ms": float(np.percentile(fl, 50)),
        "flown_p99_ms": float(np.percentile(fl, 99)),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1000)
    parser.add_argument("--rate-hz", type=float, default=50.0)
    parser.add_argument("--vehicles", type=int, nargs="+", default=[1, 50])
    parser.add_argument("--base-port", type=int, default=22000)
    args = parser.parse_args()
    for n in args.vehicles:
        print(json.dumps(measure(args.samples, n, args.rate_hz, args.base_port)), flush=True)


if __name__ == "__main__":
    main()
