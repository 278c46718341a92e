"""``python -m comms.router``: a Zenoh router (``zenoh.open`` in router mode) for multi-machine deployments.

One router per host; routers connect to each other; every FloodWatch process on a host joins as a client of the
local router (``--zenoh-mode client --connect tcp/127.0.0.1:7447``). Example for two hosts::

    hostA$ python -m comms.router --listen tcp/0.0.0.0:7447
    hostB$ python -m comms.router --listen tcp/0.0.0.0:7447 --connect tcp/hostA:7447
"""

from __future__ import annotations

import argparse
import signal
import sys
import threading
from collections.abc import Sequence

from comms.zenoh_session import ZenohConfig, ZenohOpenError, ZenohSession


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m comms.router", description="Zenoh router for FloodWatch hosts.")
    parser.add_argument("--listen", action="append", default=None, metavar="ENDPOINT", help="default tcp/0.0.0.0:7447")
    parser.add_argument("--connect", action="append", default=[], metavar="ENDPOINT", help="other hosts' routers")
    parser.add_argument("--duration-s", type=float, default=None, help="stop after this many seconds")
    args = parser.parse_args(argv)
    try:
        config = ZenohConfig.router(args.listen or ("tcp/0.0.0.0:7447",), args.connect)
    except ValueError as error:
        print(f"comms.router: {error}", file=sys.stderr)
        return 2
    stop = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())
    try:
        with ZenohSession(config) as session:
            print(f"comms.router: zid {session.zid} listening on {', '.join(config.listen)}", file=sys.stderr, flush=True)
            stop.wait(args.duration_s)
    except ZenohOpenError as error:
        print(f"comms.router: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
