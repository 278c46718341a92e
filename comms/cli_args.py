"""Command-line options shared by every process that joins Zenoh (agents, radio, router, ground station).

One spelling everywhere: ``--zenoh-mode peer|client``, ``--connect ENDPOINT`` (repeatable), ``--listen ENDPOINT``
(repeatable). Defaults: a member peer of the mission hub on ``tcp/127.0.0.1:7447``.
"""

from __future__ import annotations

import argparse

from comms.zenoh_session import DEFAULT_ENDPOINT, ZenohConfig


def add_zenoh_arguments(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("zenoh")
    group.add_argument("--zenoh-mode", choices=("peer", "client"), default="peer",
                       help="peer on this machine (default) or client of a router (multi-machine)")
    group.add_argument("--connect", action="append", default=None, metavar="ENDPOINT",
                       help=f"endpoint to connect to, repeatable (default {DEFAULT_ENDPOINT})")
    group.add_argument("--listen", action="append", default=None, metavar="ENDPOINT",
                       help="endpoint to listen on in peer mode, repeatable (default tcp/127.0.0.1:0)")


def zenoh_config_from_args(args: argparse.Namespace) -> ZenohConfig:
    """Build the ZenohConfig; raises ValueError with a one-line message on a bad endpoint."""
    connect = tuple(args.connect or (DEFAULT_ENDPOINT,))
    if args.zenoh_mode == "client":
        return ZenohConfig.client(*connect)
    listen = tuple(args.listen or ("tcp/127.0.0.1:0",))
    return ZenohConfig(mode="peer", listen=listen, connect=connect)
