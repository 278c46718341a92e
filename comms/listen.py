"""``python -m comms.listen``: watch a running mission's public keys from outside, one JSON line per event.

Joins as a Zenoh client (default ``tcp/127.0.0.1:7447``, the mission hub) and prints the drones' states, the flood
polygon (its properties and vertex count) and liveliness changes. What it does any Zenoh client can do: the public
keys are plain MessagePack maps and GeoJSON (a drone's state is followed by its 31-byte signature block, a second
MessagePack object, which a listener without the mission key skips unchecked). Example::

    python -m comms.listen --mission circle --duration-s 10
"""

from __future__ import annotations

import argparse
import json
import signal
import sys
import threading
import time
from collections.abc import Sequence

from comms.cli_args import add_tls_arguments, tls_from_args
from comms.keys import KeyNameError, MissionKeys
from comms.latest_buffer import LatestValueBuffer
from comms.messages import FloodPolygon, NeighbourState, decode
from comms.signing import unsigned_body
from comms.zenoh_session import DEFAULT_ENDPOINT, ZenohConfig, ZenohOpenError, ZenohSession


def describe(keys: MissionKeys, key: str, payload: bytes, kind: str) -> dict | None:
    """One printable record for a received sample (None for keys this tool does not show)."""
    if key.startswith(keys.prefix + "/alive/"):
        return {"key": key, "alive": kind == "put"}
    if key == keys.polygon:
        poly = decode(FloodPolygon, payload)
        if poly is None:
            return {"key": key, "error": "undecodable polygon"}
        props = poly.properties
        return {"key": key, "t_s": props.t_s, "area_m2": round(props.area_m2, 1), "perimeter_m": round(props.perimeter_m, 1),
                "vertices": len(poly.geometry.coordinates[0]) - 1}
    if keys.vehicle_id_of(key) is not None and key.endswith("/state"):
        s = decode(NeighbourState, unsigned_body(payload))
        if s is None:
            return {"key": key, "error": "undecodable state"}
        return {"key": key, "id": s.sender_id, "role": s.role, "seq": s.seq, "t_s": round(s.t_s, 3),
                "en_m": [round(v, 2) for v in s.position_en_m], "alt_m": round(s.altitude_m, 2), "group": s.group}
    return None


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m comms.listen", description="Print a mission's public Zenoh traffic.")
    parser.add_argument("--mission", default="circle")
    parser.add_argument("--connect", action="append", default=None, metavar="ENDPOINT", help=f"default {DEFAULT_ENDPOINT}")
    parser.add_argument("--duration-s", type=float, default=None)
    add_tls_arguments(parser)
    parser.add_argument("--every-s", type=float, default=1.0, help="print each key at most this often (states are 20 Hz)")
    args = parser.parse_args(argv)
    try:
        keys = MissionKeys(args.mission)
        tls = tls_from_args(args)
        config = ZenohConfig(mode="client", connect=tuple(args.connect or (DEFAULT_ENDPOINT,)),
                             extra_json5=() if tls is None else tls.json5_items())
    except (ValueError, KeyNameError) as error:
        print(f"comms.listen: {error}", file=sys.stderr)
        return 2
    stop = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())
    deadline = None if args.duration_s is None else time.monotonic() + args.duration_s
    try:
        with ZenohSession(config) as session:
            buf = LatestValueBuffer()
            session.subscribe(f"{keys.prefix}/uav/*/state", buf)
            session.subscribe(keys.polygon, buf)
            session.subscribe_alive(keys.all_alive, buf)
            last_print: dict[str, float] = {}
            while not stop.is_set() and (deadline is None or time.monotonic() < deadline):
                buf.wait(0.1)
                now = time.monotonic()
                for item in buf.drain():
                    is_event = "/alive/" in item.key
                    if not is_event and now - last_print.get(item.key, -1e9) < args.every_s:
                        continue
                    record = describe(keys, item.key, item.payload, item.kind)
                    if record is not None:
                        last_print[item.key] = now
                        print(json.dumps(record), flush=True)
    except ZenohOpenError as error:
        print(f"comms.listen: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
