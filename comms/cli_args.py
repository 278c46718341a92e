"""Command-line options shared by every process that joins Zenoh (agents, radio, router, ground station).

One spelling everywhere: ``--zenoh-mode peer|client``, ``--connect ENDPOINT`` (repeatable), ``--listen ENDPOINT``
(repeatable). Defaults: a member peer of the mission hub on ``tcp/127.0.0.1:7447``. Across hosts, ``--tls-ca``,
``--tls-cert`` and ``--tls-key`` give this host's identity for TLS with mutual authentication (``tls/...``
endpoints; see :mod:`comms.link_security`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from comms.link_security import TlsIdentity
from comms.zenoh_session import DEFAULT_ENDPOINT, ZenohConfig


def add_tls_arguments(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("TLS (multi-host)")
    group.add_argument("--tls-ca", type=Path, metavar="PEM", help="the mission CA certificate")
    group.add_argument("--tls-cert", type=Path, metavar="PEM", help="this host's certificate")
    group.add_argument("--tls-key", type=Path, metavar="PEM", help="this host's private key")


def tls_from_args(args: argparse.Namespace) -> TlsIdentity | None:
    """This host's TLS identity, None without ``--tls-*``; raises ValueError when only some are given."""
    files = (args.tls_ca, args.tls_cert, args.tls_key)
    if not any(files):
        return None
    if not all(files):
        raise ValueError("--tls-ca, --tls-cert, --tls-key: give all three")
    return TlsIdentity(*files)


def add_zenoh_arguments(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("zenoh")
    group.add_argument("--zenoh-mode", choices=("peer", "client"), default="peer",
                       help="peer on this machine (default) or client of a router (multi-machine)")
    group.add_argument("--connect", action="append", default=None, metavar="ENDPOINT",
                       help=f"endpoint to connect to, repeatable (default {DEFAULT_ENDPOINT})")
    group.add_argument("--listen", action="append", default=None, metavar="ENDPOINT",
                       help="endpoint to listen on in peer mode, repeatable (default tcp/127.0.0.1:0)")
    add_tls_arguments(parser)


def zenoh_config_from_args(args: argparse.Namespace) -> ZenohConfig:
    """Build the ZenohConfig; raises ValueError with a one-line message on a bad endpoint."""
    connect = tuple(args.connect or (DEFAULT_ENDPOINT,))
    tls = tls_from_args(args)
    extra = () if tls is None else tls.json5_items()
    if args.zenoh_mode == "client":
        return ZenohConfig(mode="client", connect=connect, extra_json5=extra)
    listen = tuple(args.listen or ("tcp/127.0.0.1:0",))
    return ZenohConfig(mode="peer", listen=listen, connect=connect, extra_json5=extra)
