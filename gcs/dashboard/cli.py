"""``python -m gcs.dashboard --mission circle --connect tcp/HOST:7447 --port 8080``: the live map for a mission
reachable over Zenoh (the rescue centre's own machine), and the process ``gcs.mission`` starts for itself.

Bad input prints one line naming the flag and exits 2; an unreachable hub or unreadable tile file exits 1.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from comms.cli_args import add_zenoh_arguments, zenoh_config_from_args
from comms.keys import KeyNameError, validate_mission
from comms.zenoh_session import ZenohOpenError
from gcs.dashboard.cli_checks import check_dashboard_args
from gcs.dashboard.ports import DEFAULT_HOST, DEFAULT_PORT, TOKEN_ENV, choose_port, dashboard_url, is_loopback
from gcs.dashboard.server import ServerOptions, serve
from gcs.dashboard.tiles import TilesError
from gcs.one_line_argparse import EXIT_USAGE, OneLineArgumentParser


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineArgumentParser(prog="python -m gcs.dashboard", label="gcs.dashboard",
                                   description="The live flood map of a running mission, in a browser, offline.")
    parser.add_argument("--mission", required=True, help="mission name (the scenario's name unless set otherwise)")
    parser.add_argument("--host", default=DEFAULT_HOST,
                        help="address to listen on (default 127.0.0.1; any other prints a warning)")
    parser.add_argument("--port", type=int, default=DEFAULT_PORT,
                        help="port (default 8080; when busy a free one, printed; 0: any free one)")
    parser.add_argument("--dashboard-token", "--token", dest="token", default=None, metavar="TOKEN",
                        help=f"operator token for hold / resume / land-all (default: ${TOKEN_ENV}; none: read-only)")
    parser.add_argument("--tiles", type=Path, default=None, metavar="FILE",
                        help="local raster MBTiles or PMTiles file as base map")
    parser.add_argument("--key-file", type=Path, default=None, metavar="FILE",
                        help="the mission key (mode 0600) that signs operator requests; without it: read-only")
    add_zenoh_arguments(parser)
    parser.set_defaults(zenoh_mode="client")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(sys.argv[1:] if argv is None else list(argv))
    token = args.token if args.token is not None else (os.environ.get(TOKEN_ENV) or None)

    def fail(message: str) -> None:
        print(f"gcs.dashboard: {message}", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)

    check_dashboard_args(args.port, args.token, args.tiles, fail)
    try:
        validate_mission(args.mission)
        zenoh = zenoh_config_from_args(args)
    except (KeyNameError, ValueError) as exc:
        fail(f"--mission/--connect: {exc}")
    try:
        port = choose_port(args.host, args.port)
    except OSError as exc:
        fail(f"--host {args.host}: {exc}")
    options = ServerOptions(mission=args.mission, zenoh=zenoh, host=args.host, port=port, token=token,
                            tiles=args.tiles, key_file=args.key_file)
    if not is_loopback(args.host):
        print(f"gcs.dashboard: warning: listening on {args.host}, reachable from other machines"
              f"{'' if token else ' (read-only: no token)'}", file=sys.stderr)
    print(f"gcs.dashboard: live map of mission {args.mission} at {dashboard_url(args.host, port)} "
          f"({'operator commands need the token' if token else 'read-only'})", flush=True)
    try:
        asyncio.run(serve(options))
    except (ZenohOpenError, TilesError) as exc:
        print(f"gcs.dashboard: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    return 0
