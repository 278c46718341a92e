"""Which UDP port each vehicle's onboard (API) link talks to: PX4 SITL's convention, minus its one trap.

PX4 SITL instance i sends its onboard/API link to 14540 + i and its GCS link to 14550. With more than ten vehicles
instance 10 would then send its API link to 14550, QGroundControl's port, and the ground station and that vehicle's
agent would fight over one socket. We keep PX4's numbering and skip the GCS port: instances 0-9 use 14540-14549 as
PX4 does, instance 10 uses 14551, and so on. Pure, so the fleet and whoever starts the agents agree.
"""

from __future__ import annotations


def onboard_port(base_port: int, instance: int, gcs_port: int) -> int:
    """UDP port of instance ``instance``'s onboard link (0-based), skipping ``gcs_port``."""
    port = base_port + instance
    if base_port <= gcs_port <= port:
        port += 1
    return port


def onboard_port_range(base_port: int, vehicles: int, gcs_port: int) -> tuple[int, int]:
    """First and last onboard port of a fleet of ``vehicles`` (the range may step over ``gcs_port``)."""
    return onboard_port(base_port, 0, gcs_port), onboard_port(base_port, vehicles - 1, gcs_port)
