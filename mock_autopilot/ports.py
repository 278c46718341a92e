"""Which UDP port each vehicle's onboard (API) link talks to: PX4 SITL's convention, minus its one trap.

PX4 SITL instance i sends its onboard/API link to 14540 + i and its GCS link to 14550. With more than ten vehicles
instance 10 would then send its API link to 14550, QGroundControl's port, and the ground station and that vehicle's
agent would fight over one socket. We keep PX4's numbering and skip the GCS port: instances 0-9 use 14540-14549 as
PX4 does, instance 10 uses 14551, and so on. Pure, so the fleet and whoever starts the agents agree; the hosts the
links bind and send to (:class:`LinkHosts`) likewise.
"""

from __future__ import annotations

import ipaddress
from collections.abc import Sequence
from dataclasses import dataclass


def onboard_port(base_port: int, instance: int, gcs_port: int) -> int:
    """UDP port of instance ``instance``'s onboard link (0-based), skipping ``gcs_port``."""
    port = base_port + instance
    if base_port <= gcs_port <= port:
        port += 1
    return port


def onboard_port_range(base_port: int, vehicles: int, gcs_port: int) -> tuple[int, int]:
    """First and last onboard port of a fleet of ``vehicles`` (the range may step over ``gcs_port``)."""
    return onboard_port(base_port, 0, gcs_port), onboard_port(base_port, vehicles - 1, gcs_port)


@dataclass(frozen=True)
class LinkHosts:
    """Where the fleet's MAVLink links live: the address their sockets bind (``bind``, default ``host``) and where
    each vehicle's onboard link sends: ``host``, unless its companion computer sits at another address
    (``onboard_partners``: vehicle id -> IP, what PX4 sets with ``mavlink start -t <partner IP>``). A companion
    computer on another machine needs both: a partner address for its vehicle and the fleet bound to an interface
    that reaches it (``0.0.0.0``: every one, as PX4 binds)."""

    host: str = "127.0.0.1"
    bind: str | None = None
    onboard_partners: tuple[tuple[int, str], ...] = ()

    @property
    def bind_host(self) -> str:
        return self.host if self.bind is None else self.bind

    def onboard_host(self, vehicle_id: int) -> str:
        return dict(self.onboard_partners).get(vehicle_id, self.host)


def parse_onboard_partners(specs: Sequence[str]) -> tuple[tuple[int, str], ...]:
    """``IDS=IP`` items (``3=10.0.0.5``, ``1-4=10.0.0.2``, ``1,5=...``) as (vehicle id, IP) pairs; raises ValueError
    naming the bad item."""
    pairs: dict[int, str] = {}
    for spec in specs:
        ids, sep, ip = spec.partition("=")
        try:
            if not sep or not ip:
                raise ValueError
            ipaddress.ip_address(ip)
            for part in ids.split(","):
                first, _, last = part.partition("-")
                for vid in range(int(first), int(last or first) + 1):
                    pairs[vid] = ip
        except ValueError:
            raise ValueError(f"--onboard-partner {spec!r}: expected VEHICLE_IDS=IP, e.g. 1-4=10.0.0.2") from None
    return tuple(sorted(pairs.items()))


def link_hosts(bind: str | None, partner_specs: Sequence[str]) -> LinkHosts:
    """The fleet's ``LinkHosts`` from its command line (``--bind``, ``--onboard-partner``); raises ValueError."""
    if bind is not None:
        try:
            ipaddress.ip_address(bind)
        except ValueError:
            raise ValueError(f"--bind {bind!r}: expected an IP address, e.g. 0.0.0.0") from None
    hosts = LinkHosts(bind=bind, onboard_partners=parse_onboard_partners(partner_specs))
    if ipaddress.ip_address(hosts.bind_host).is_loopback:
        remote = [ip for _, ip in hosts.onboard_partners if not ipaddress.ip_address(ip).is_loopback]
        if remote:
            raise ValueError(f"--bind {hosts.bind_host}: a loopback socket cannot reach the onboard partner {remote[0]} "
                             f"(bind 0.0.0.0 or that interface's address)")
    return hosts
