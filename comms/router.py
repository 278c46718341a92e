"""``python -m comms.router``: a Zenoh router (``zenoh.open`` in router mode) for multi-machine deployments.

One router per host; routers connect to each other; every FloodWatch process on a host joins as a client of the
local router. Across a network the links must be authenticated: with ``--tls-ca/--tls-cert/--tls-key`` (files from
``python -m comms.certificates``) the router speaks TLS with mutual authentication, so a peer without a certificate
from the mission CA cannot connect, and it applies the mission's access control (:mod:`comms.link_security`):
only ``--ground-station`` identities publish commands, each ``--drone-host NAME=IDS`` only its drones' states,
``--reader`` identities (the rescue centre) only subscribe to the public keys. Example for two hosts::

    gcs$   python -m comms.router --listen tls/0.0.0.0:7448 --connect tcp/127.0.0.1:7447 --trust-loopback \\
               --tls-ca ca.pem --tls-cert ground-station.pem --tls-key ground-station-key.pem \\
               --mission circle --drone-host drone-host-1=1-13
    drone$ python -m comms.router --listen tls/127.0.0.1:7447 --connect tls/gcs:7448 --tls-ca ca.pem \\
               --tls-cert drone-host-1.pem --tls-key drone-host-1-key.pem --mission circle --drone-host drone-host-1=1-13

Without TLS files the router is open (plain TCP, no access control): for one trusted machine only.
"""

from __future__ import annotations

import argparse
import signal
import sys
import threading
from collections.abc import Sequence

from comms.cli_args import add_tls_arguments, tls_from_args
from comms.keys import KeyNameError, validate_mission
from comms.link_security import AccessPolicy, parse_drone_host
from comms.zenoh_session import ZenohConfig, ZenohOpenError, ZenohSession


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m comms.router", description="Zenoh router for FloodWatch hosts.")
    parser.add_argument("--listen", action="append", default=None, metavar="ENDPOINT", help="default tcp/0.0.0.0:7447")
    parser.add_argument("--connect", action="append", default=[], metavar="ENDPOINT", help="other hosts' routers")
    parser.add_argument("--duration-s", type=float, default=None, help="stop after this many seconds")
    add_tls_arguments(parser)
    acl = parser.add_argument_group("access control (with TLS)")
    acl.add_argument("--mission", help="the mission whose keys the access control covers (required with TLS)")
    acl.add_argument("--ground-station", action="append", default=None, metavar="NAME",
                     help="certificate name allowed to command (default ground-station)")
    acl.add_argument("--drone-host", action="append", default=[], metavar="NAME=IDS",
                     help="a drone host's certificate name and its vehicle ids, e.g. drone-host-1=1-7 (repeatable)")
    acl.add_argument("--reader", action="append", default=None, metavar="NAME",
                     help="certificate name that may only read the public keys (default rescue-centre)")
    acl.add_argument("--trust-loopback", action="store_true",
                     help="ground-station host only: plain TCP over loopback (the mission hub) has its rights")
    return parser


def config_from_args(args: argparse.Namespace) -> ZenohConfig:
    """The router's configuration; raises ValueError (one line naming the flag) on bad input."""
    tls = tls_from_args(args)
    extra: tuple[tuple[str, str], ...] = ()
    if tls is not None:
        if not args.mission:
            raise ValueError("--mission: required with --tls-* (the access control is per mission)")
        policy = AccessPolicy(validate_mission(args.mission), tuple(args.ground_station or ("ground-station",)),
                              dict(parse_drone_host(h) for h in args.drone_host), tuple(args.reader or ("rescue-centre",)),
                              args.trust_loopback)
        extra = tls.json5_items() + policy.json5_items()
    elif args.drone_host or args.mission or args.trust_loopback:
        raise ValueError("--mission/--drone-host: access control needs --tls-ca, --tls-cert and --tls-key")
    config = ZenohConfig.router(args.listen or ("tcp/0.0.0.0:7447",), args.connect)
    return ZenohConfig(mode="router", listen=config.listen, connect=config.connect, extra_json5=extra)


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        config = config_from_args(args)
    except (ValueError, KeyNameError) as error:
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
