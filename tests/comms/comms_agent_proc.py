"""A minimal agent process for the comms tests: publishes its state at a rate, records whom it hears.

Not a test module (no ``test_`` prefix). Prints "READY" once joined, "DEAD <id>" as soon as it learns a
neighbour's liveliness token vanished, and one JSON line on stdout when it stops (SIGTERM or duration):
{"id": ..., "heard": {sender: count}, "dead": [...], "sent": n}.
"""

from __future__ import annotations

import argparse
import json
import signal
import sys
import threading
import time
from collections import Counter
from dataclasses import replace
from pathlib import Path

from comms.cli_args import add_tls_arguments, tls_from_args
from comms.key_file import read_key_file
from comms.keys import MissionKeys
from comms.messages import NeighbourState
from comms.neighbour_table import NeighbourTable
from comms.swarm_link import SwarmLink
from comms.zenoh_session import ZenohConfig, ZenohSession


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--hub", required=True)
    p.add_argument("--mission", required=True)
    p.add_argument("--id", type=int, required=True)
    p.add_argument("--claim", type=float, nargs=2, default=(0.0, 0.0))
    p.add_argument("--rate-hz", type=float, default=20.0)
    p.add_argument("--duration-s", type=float, default=30.0)
    p.add_argument("--via-radio", action="store_true")
    p.add_argument("--client", action="store_true", help="join as a client of the router at --hub (not a peer)")
    p.add_argument("--key-file", type=Path, default=None, help="the mission key: sign what it sends, check what it hears")
    add_tls_arguments(p)
    a = p.parse_args()
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    heard: Counter[int] = Counter()
    dead: list[int] = []
    keys = MissionKeys(a.mission)
    table = NeighbourTable(own_id=a.id, period_s=1.0 / a.rate_hz)
    sent = 0
    config = ZenohConfig.client(a.hub) if a.client else ZenohConfig.member(a.hub)
    tls = tls_from_args(a)
    if tls is not None:
        config = replace(config, extra_json5=tls.json5_items())
    key = None if a.key_file is None else read_key_file(a.key_file)
    with ZenohSession(config) as session:
        link = SwarmLink(session, keys, a.id, via_radio=a.via_radio, key=key)
        print("READY", flush=True)
        t0 = time.monotonic()
        next_t = t0
        while not stop.is_set() and time.monotonic() - t0 < a.duration_s:
            now = time.monotonic()
            if now >= next_t:
                link.publish(NeighbourState(sender_id=a.id, role="boundary", seq=sent, t_s=now - t0,
                                            position_en_m=tuple(a.claim), altitude_m=10.0))
                sent += 1
                next_t += 1.0 / a.rate_hz
            update = link.update_table(table, now - t0)
            heard.update(s.sender_id for s in update.states)
            dead.extend(update.dead)
            for vid in update.dead:
                print(f"DEAD {vid}", flush=True)
            link.wait(max(0.0, min(0.01, next_t - time.monotonic())))
    print(json.dumps({"id": a.id, "heard": {str(k): v for k, v in heard.items()}, "dead": dead, "sent": sent}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
