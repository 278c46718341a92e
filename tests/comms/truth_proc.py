"""A simulator's truth for the comms tests: what ``mock_autopilot.sim_bridge`` publishes on the ground-station host.

Not a test module (no ``test_`` prefix). Joins the mission hub at ``--connect`` as a member peer and publishes a
``GroundTruth`` of the vehicles given as ``ID:EAST,NORTH`` (10 m up, standing still) at 20 Hz until SIGTERM;
prints "READY" once joined.
"""

from __future__ import annotations

import argparse
import signal
import sys
import threading
import time

from comms.keys import MissionKeys
from comms.messages import GroundTruth, encode
from comms.zenoh_session import ZenohConfig, ZenohSession


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--connect", required=True)
    p.add_argument("--mission", required=True)
    p.add_argument("--vehicles", nargs="+", required=True, metavar="ID:EAST,NORTH")
    a = p.parse_args()
    ids, positions = [], []
    for text in a.vehicles:
        vid, _, en = text.partition(":")
        east, north = (float(v) for v in en.split(","))
        ids.append(int(vid))
        positions.append((east, north, 10.0))
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    keys = MissionKeys(a.mission)
    with ZenohSession(ZenohConfig.member(a.connect)) as session:
        print("READY", flush=True)
        t0 = time.monotonic()
        while not stop.wait(0.05):
            session.put(keys.truth, encode(GroundTruth(t_s=time.monotonic() - t0, vehicle_ids=ids,
                                                       positions_enu_m=positions)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
