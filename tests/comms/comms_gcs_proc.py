"""A minimal ground-station process for the comms tests: hears the drones' states, publishes a polygon each second.

Not a test module (no ``test_`` prefix). Joins as a client of ``--hub``; once it has heard a drone it publishes a
flood polygon around the positions heard on the public polygon key, so that a listener elsewhere can receive it.
Prints one JSON line when it stops (SIGTERM or duration): {"heard": [ids], "polygons": n}.
"""

from __future__ import annotations

import argparse
import json
import signal
import sys
import threading
import time

import numpy as np

from comms.frames import GeodeticHome
from comms.keys import MissionKeys
from comms.messages import encode, flood_polygon_from_enu
from comms.swarm_link import SwarmLink
from comms.zenoh_session import ZenohConfig, ZenohSession


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--hub", required=True)
    p.add_argument("--mission", required=True)
    p.add_argument("--drones", required=True, help="comma-separated ids expected")
    p.add_argument("--duration-s", type=float, default=30.0)
    a = p.parse_args()
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    keys = MissionKeys(a.mission)
    positions: dict[int, tuple[float, float]] = {}
    polygons = 0
    with ZenohSession(ZenohConfig.client(a.hub)) as session:
        link = SwarmLink(session, keys, None, via_radio=False, participant="gcs")
        t0 = time.monotonic()
        next_polygon = t0 + 1.0
        while not stop.is_set() and time.monotonic() - t0 < a.duration_s:
            for state in link.poll().states:
                positions[state.sender_id] = state.position_en_m
            if positions and time.monotonic() >= next_polygon:
                heard = np.array(list(positions.values()), dtype=float)
                low, high = heard.min(axis=0) - 2.0, heard.max(axis=0) + 2.0
                ring = [(low[0], low[1]), (high[0], low[1]), (high[0], high[1]), (low[0], high[1])]
                feature = flood_polygon_from_enu(ring, GeodeticHome(), mission=a.mission, t_s=time.monotonic() - t0,
                                                 vehicle_ids=sorted(positions))
                session.put(keys.polygon, encode(feature))
                polygons += 1
                next_polygon += 1.0
            link.wait(0.05)
    print(json.dumps({"heard": sorted(positions), "polygons": polygons}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
