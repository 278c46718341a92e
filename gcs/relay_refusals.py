"""Relayed copies refused as impossible: the run's one line about them in events.log, the same in both engines.

Every receiver admits relayed copies by the rules of :mod:`vehicle_agents.core.relay_admission` (a copy from the
future, or one whose ``seq`` runs ahead of what its origin could have sent, is dropped and counted). On an honest
run nothing is refused; a count above zero means a key holder injected copies, or a clock problem (an agent whose
clock runs ahead of the others'). The lockstep engine counts in its onboard state and ground node, the processes
engine reads each agent's exit report and its own ground node's count; both record the figures in the
:class:`~gcs.mission_record.MissionRecord` (metrics.json: summary and per vehicle) and write this line.
"""

from __future__ import annotations

from collections.abc import Sequence


def refused_copies_line(vehicle_ids: Sequence[int], per_vehicle: Sequence[int | None],
                        ground_station: int | None) -> str:
    """One events.log line: the total refused by the vehicles (those that reported), each vehicle that refused any,
    the vehicles whose count is unknown (no exit report), and the ground station's count when it is a radio node."""
    known = [(vid, count) for vid, count in zip(vehicle_ids, per_vehicle) if count is not None]
    text = f"relayed copies refused as impossible: {sum(count for _, count in known)} by the vehicles"
    refusing = [f"{vid}: {count}" for vid, count in known if count]
    if refusing:
        text += f" ({', '.join(refusing)})"
    unknown = [str(vid) for vid, count in zip(vehicle_ids, per_vehicle) if count is None]
    if unknown:
        text += f", unknown for vehicles {', '.join(unknown)} (no exit report)"
    if ground_station is not None:
        text += f", {ground_station} by the ground station's radio node"
    return text
