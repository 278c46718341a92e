"""What the laws read of the neighbours when the neighbour filter is on: each table entry's non-kinematic fields
(role, group, flags, ring radius) with the filter's position and velocity at the control time (pure).

The neighbour table (:mod:`vehicle_agents.core.neighbours`) still keeps the newest message per sender and applies
departures; it holds entries for :func:`table_hold_s`, longer than any track can live, so that the filter's bound
(:mod:`vehicle_agents.core.neighbour_filter`), not a count of periods, decides when a neighbour is no longer used.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from comms.messages import NeighbourState
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.types import NeighbourInfo
from vehicle_agents.core.neighbour_filter import FilterNoise, TrackBank, at_time, update, without
from vehicle_agents.onboard_view import neighbour_info_at

_LONGEST_HOLD_S = 60.0


def filter_noise(params: ControlParams) -> FilterNoise:
    return FilterNoise(params.neighbour_accel_psd_m2ps3, params.neighbour_position_std_m,
                       params.neighbour_velocity_std_mps, params.neighbour_position_bound_m)


def table_hold_s(params: ControlParams) -> float:
    """How long the table keeps a silent sender's message: twice the gap after which even a track known exactly
    exceeds the bound (``q τ³ / 3 = bound²``), plus the plain timeout."""
    q = params.neighbour_accel_psd_m2ps3
    if q <= 0.0:
        return _LONGEST_HOLD_S
    horizon_s = (3.0 * params.neighbour_position_bound_m ** 2 / q) ** (1.0 / 3.0)
    return min(_LONGEST_HOLD_S, params.neighbour_timeout_s + 2.0 * horizon_s)


def track_step(bank: TrackBank, states: Sequence[NeighbourState], departed: frozenset[int], own_id: int,
               noise: FilterNoise) -> TrackBank:
    """The bank after one inbox: departed senders removed, every other state (not one's own) filed as a measurement.

    A state object met again later in the inbox (an agent decodes a relayed copy once for every carrier that brings
    it) is filed once: :func:`update` keeps the first of equal measurements of a sender, so this changes nothing but
    the work.
    """
    firsts = {id(m): m for m in states if m.sender_id != own_id and m.sender_id not in departed}
    return update(without(bank, departed), list(firsts.values()), noise)


def filtered_infos(bank: TrackBank, table: Mapping[int, NeighbourState], t_s: float,
                   noise: FilterNoise) -> tuple[TrackBank, list[NeighbourInfo]]:
    """The live tracks at ``t_s`` (the others dropped at the bound) as the laws read them, in id order: position and
    velocity from the track (views into the predicted states), the rest from the newest message (its own
    kinematics are not read, so nothing of it is converted)."""
    bank, x, _ = at_time(bank, t_s, noise)
    infos = []
    for row, vid in enumerate(bank.ids.tolist()):
        msg = table.get(vid)
        if msg is not None:
            infos.append(neighbour_info_at(msg, x[row, :2], x[row, 2:], 0.0))
    return bank, infos
