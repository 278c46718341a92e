"""One onboard step for N drones: flight phase, neighbours, control law, setpoint and state message (pure).

The order inside a step is the agent's: decide the flight phase from telemetry and the ground station's order
(:func:`vehicle_agents.flight_phase.next_phase`), file the inbox into the neighbour table
(:mod:`vehicle_agents.core.neighbours`), correct a GPS-less drone's drifting odometry from the relative positions
it senses of its neighbours (:mod:`vehicle_agents.core.cooperative_position`; its position is then the corrected
one everywhere below), run the control law of the drone's role when the phase says fly
(:func:`vehicle_agents.control.step.control_step`: eq 8 + Algorithm 1, eq 9, eq 10) on the camera result it trusts
(:mod:`vehicle_agents.perception.edge_trust`: one frame contradicting a recent edge is held, not obeyed), its
collision barrier keeping clear of the neighbours where its relative-position sensor sees them
(:mod:`vehicle_agents.core.sensed_neighbours`), and build the state message it broadcasts
(:func:`vehicle_agents.onboard_view.state_message`, edge points subsampled there and only there).
The laws still loop over drones; the interface is arrays in, arrays out, so that it holds when they no longer do.
A neighbour's message is turned into what the laws read once per step, however many drones heard it, and the laws
get their neighbours in id order whatever order the radio delivered them in.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import msgspec
import numpy as np
from numpy.typing import NDArray

from comms.messages import HeardState, NeighbourRanging, NeighbourState
from vehicle_agents.control.memory import ControlMemory
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.step import control_step, hover_step, initial_memory, own_broadcast
from vehicle_agents.control.types import NeighbourInfo, OwnState
from vehicle_agents.core.cooperative_position import (
    NO_CORRECTION,
    PositionCorrection,
    correction_step,
    corrects_odometry,
)
from vehicle_agents.core.filtered_neighbours import filter_noise, filtered_infos, table_hold_s, track_step
from vehicle_agents.core.neighbour_filter import EMPTY_BANK, FilterNoise, TrackBank
from vehicle_agents.core.neighbours import EMPTY_INBOX, Inbox, heard_after
from vehicle_agents.core.relay import relay_copies, unpacked
from vehicle_agents.core.relay_admission import admitted
from vehicle_agents.core.sensed_neighbours import sensed_offsets
from vehicle_agents.core.telemetry import TelemetryBatch
from vehicle_agents.flight_phase import Action, Command, Phase, PhaseInputs, PhaseLimits, next_phase
from vehicle_agents.onboard_view import neighbour_info, own_state, state_message, velocity_ned
from vehicle_agents.perception.edge_trust import NO_TRUST, EdgeTrust, trusted_result
from vehicle_agents.perception.result import PerceptionResult

SETPOINT_ACTIONS = frozenset({Action.FLY, Action.HOVER})
"""Actions that stream a velocity setpoint to the autopilot this period."""


@dataclass(frozen=True)
class OnboardPlan:
    """The N drones a core instance flies: ids, roles, pads [m; mission E, N], GPS, and the shared parameters."""

    vehicle_ids: tuple[int, ...]
    roles: tuple[str, ...]
    pads_en_m: tuple[tuple[float, float], ...]
    has_gps: tuple[bool, ...]
    params: ControlParams
    limits: PhaseLimits = field(default_factory=PhaseLimits)

    def __post_init__(self) -> None:
        n = len(self.vehicle_ids)
        if not (len(self.roles) == len(self.pads_en_m) == len(self.has_gps) == n):
            raise ValueError("OnboardPlan: vehicle_ids, roles, pads_en_m and has_gps must have one entry per drone")

    def __len__(self) -> int:
        return len(self.vehicle_ids)


@dataclass(frozen=True)
class GroundOrder:
    """The ground station's newest order as one drone received it (None before the first).

    ``age_s`` is how long ago it arrived (wall seconds in an agent: the ground station repeats its order twice a
    second, and its silence is a link matter); ``flood_clock_start_t_s`` the mission time the flood clock started.
    """

    command: Command | None = None
    age_s: float | None = None
    flood_clock_start_t_s: float | None = None


NO_ORDER = GroundOrder()


@dataclass(frozen=True)
class OnboardInputs:
    """Everything N drones know at mission time ``t_s``; per-drone sequences have one entry per plan row."""

    t_s: float
    telemetry: TelemetryBatch
    perception: Sequence[PerceptionResult | None]
    """Each drone's result of its newest camera frame (None before the first): perception runs before the core."""
    inbox: Sequence[Inbox]
    orders: Sequence[GroundOrder]
    stop: Sequence[bool] | None = None
    """Per drone: the process is being stopped (SIGTERM, Ctrl-C) and must leave at this step."""
    ranging: Sequence[NeighbourRanging | None] = ()
    """Each drone's newest relative-position measurement of its neighbours (None before the first; empty: none)."""


@dataclass(frozen=True)
class OnboardState:
    """What the core remembers between steps (replaced, never mutated)."""

    phases: tuple[Phase, ...]
    memories: tuple[ControlMemory, ...]
    heard: tuple[Mapping[int, HeardState], ...]
    departed: tuple[frozenset[int], ...]
    seq: tuple[int, ...]
    tracks: tuple[TrackBank, ...] = ()
    """Each drone's neighbour filter (empty while the filter is off)."""
    trust: tuple[EdgeTrust, ...] = ()
    """Each drone's last trusted edge (:mod:`vehicle_agents.perception.edge_trust`)."""
    refused_copies: tuple[int, ...] = ()
    """Each drone's count of relayed copies refused as impossible (:mod:`vehicle_agents.core.relay_admission`)."""
    positions: tuple[PositionCorrection, ...] = ()
    """Each drone's estimate of its own odometry error (:mod:`vehicle_agents.core.cooperative_position`)."""


@dataclass(frozen=True)
class OnboardOutputs:
    """What N drones do this step."""

    actions: tuple[Action, ...]
    velocity_setpoint_ned_mps: NDArray[np.float64]
    """(N, 3) [m/s; NED]; meaningful where the action streams a setpoint (:data:`SETPOINT_ACTIONS`)."""
    yaw_ned_rad: NDArray[np.float64]
    state_messages: tuple[NeighbourState | None, ...]
    """Each drone's broadcast (None while its autopilot has never spoken: it knows nothing to tell)."""


def initial_state(plan: OnboardPlan, phase: Phase = Phase.CONNECTING) -> OnboardState:
    """Every drone at ``phase`` (an agent starts CONNECTING; lockstep starts its hovering fleet in MISSION)."""
    n = len(plan)
    return OnboardState(
        phases=(phase,) * n,
        memories=tuple(initial_memory(role, vid, plan.params) for vid, role in zip(plan.vehicle_ids, plan.roles)),
        heard=({},) * n,
        departed=(frozenset(),) * n,
        seq=(0,) * n,
        tracks=(EMPTY_BANK,) * n,
    )


def onboard_step(plan: OnboardPlan, state: OnboardState, inputs: OnboardInputs) -> tuple[OnboardOutputs, OnboardState]:
    """One control period of every drone of ``plan`` (see module doc). Pure."""
    n = len(plan)
    params = plan.params
    t_s = inputs.t_s
    phases = list(state.phases)
    memories = list(state.memories)
    heard = list(state.heard)
    departed = list(state.departed)
    seq = list(state.seq)
    tracks = list(state.tracks) if state.tracks else [EMPTY_BANK] * n
    trust = list(state.trust) if state.trust else [NO_TRUST] * n
    refused_copies = list(state.refused_copies) if state.refused_copies else [0] * n
    positions = list(state.positions) if state.positions else [NO_CORRECTION] * n
    noise = filter_noise(params) if params.neighbour_filter else None
    timeout_s = table_hold_s(params) if noise is not None else params.neighbour_timeout_s
    actions: list[Action] = []
    setpoints = np.zeros((n, 3))
    yaws = np.zeros(n)
    messages: list[NeighbourState | None] = []
    converted: dict[int, NeighbourInfo] = {}
    for i in range(n):
        tel = inputs.telemetry.vehicle(i)
        order = inputs.orders[i]
        command = Command.STOP if inputs.stop is not None and inputs.stop[i] else order.command
        silence_s = float(inputs.telemetry.link_silence_s[i])
        phase, action = next_phase(phases[i], PhaseInputs(tel, silence_s, command, order.age_s), plan.limits)
        phases[i] = phase
        actions.append(action)
        vid = plan.vehicle_ids[i]
        inbox = inputs.inbox[i] if inputs.inbox else EMPTY_INBOX
        heard[i], departed[i], tracks[i], refused = _hear(inbox, heard[i], departed[i], tracks[i], vid, t_s,
                                                          timeout_s, noise, params)
        refused_copies[i] += refused
        own = own_state(tel, plan.pads_en_m[i], plan.has_gps[i])
        ranging = inputs.ranging[i] if inputs.ranging else None
        if corrects_odometry(params.cooperative_position, params.odometry_drift_frac, plan.has_gps[i]):
            own, positions[i] = _corrected(own, positions[i], ranging, heard[i], tel.yaw_ned_rad, t_s, params)
        perception, trust[i] = trusted_result(inputs.perception[i], own.position_en_m, t_s, trust[i])
        if action in SETPOINT_ACTIONS:
            tracks[i], infos = _neighbour_infos(heard[i], tracks[i], t_s, noise, converted)
            sensed = sensed_offsets(ranging, tel.yaw_ned_rad, t_s) if params.sensed_barrier else None
            if action is Action.FLY:
                start_s = order.flood_clock_start_t_s if order.flood_clock_start_t_s is not None else t_s
                velocity, memories[i] = control_step(plan.roles[i], memories[i], own, perception, infos, params,
                                                     max(0.0, t_s - start_s), sensed)
                yaws[i] = float(velocity.yaw_ned_rad)
            else:
                velocity = hover_step(plan.roles[i], vid, own, plan.pads_en_m[i], plan.limits.takeoff_altitude_m,
                                      infos, params, sensed)
            setpoints[i] = velocity_ned(velocity)
        if not inputs.telemetry.heard(i):
            messages.append(None)
            continue
        seq[i] += 1
        message = state_message(
            seq=seq[i], t_s=t_s, broadcast=own_broadcast(memories[i], own, t_s), own=own, tel=tel,
            perception=perception, edge_points_en_m=memories[i].edge_points_en_m,
            leaving=action is Action.EXIT, low_battery=tel.battery_fraction < plan.limits.low_battery_fraction,
        )
        messages.append(_with_relayed(message, heard[i], vid, t_s, seq[i], params))
    outputs = OnboardOutputs(tuple(actions), setpoints, yaws, tuple(messages))
    new_state = replace(state, phases=tuple(phases), memories=tuple(memories), heard=tuple(heard),
                        departed=tuple(departed), seq=tuple(seq), tracks=tuple(tracks), trust=tuple(trust),
                        refused_copies=tuple(refused_copies), positions=tuple(positions))
    return outputs, new_state


def _hear(inbox: Inbox, heard: Mapping[int, HeardState], departed: frozenset[int], track: TrackBank, vehicle_id: int,
          t_s: float, timeout_s: float, noise: FilterNoise | None, params: ControlParams
          ) -> tuple[Mapping[int, HeardState], frozenset[int], TrackBank, int]:
    """File one drone's inbox: relayed copies admitted (impossible ones refused and counted), then the neighbour
    table and, when the filter is on, its tracks; returns them with the count refused."""
    refused = 0
    if params.relay_max_hops > 0 and inbox.states:
        states, refused = admitted(unpacked(inbox.states), heard, t_s, params.state_rate_hz)
        inbox = replace(inbox, states=states)
    heard, departed = heard_after(heard, departed, inbox, vehicle_id, t_s, timeout_s)
    if noise is not None:
        track = track_step(track, inbox.states, departed, vehicle_id, noise)
    return heard, departed, track, refused


def _corrected(own: OwnState, correction: PositionCorrection, ranging: NeighbourRanging | None,
               heard: Mapping[int, HeardState], yaw_ned_rad: float, t_s: float, params: ControlParams
               ) -> tuple[OwnState, PositionCorrection]:
    """The drone's own state on its corrected position, and the correction after this step's ranging."""
    correction = correction_step(correction, own.position_en_m, own.velocity_en_mps, yaw_ned_rad, ranging, heard, t_s,
                                 params.odometry_drift_frac, params.ranging_sigma_m)
    return replace(own, position_en_m=correction.corrected(own.position_en_m)), correction


def _neighbour_infos(table: Mapping[int, HeardState], track: TrackBank, t_s: float, noise: FilterNoise | None,
                     converted: dict[int, NeighbourInfo]) -> tuple[TrackBank, list[NeighbourInfo]]:
    """What the laws read of the neighbours: the filtered estimates at ``t_s`` when the neighbour filter is on,
    else the last message heard from each (converted once per message and shared across the fleet's drones)."""
    if noise is not None:
        return filtered_infos(track, table, t_s, noise)
    infos = []
    for sender in sorted(table):
        msg = table[sender]
        info = converted.get(id(msg))
        if info is None:
            info = converted[id(msg)] = neighbour_info(msg, max(0.0, t_s - msg.t_s))
        infos.append(info)
    return track, infos


def _with_relayed(message: NeighbourState, heard: Mapping[int, HeardState], vehicle_id: int, t_s: float, seq: int,
                  params: ControlParams) -> NeighbourState:
    """The drone's own state with the copies it relays this tick (every ``relay_every``-th message)."""
    if params.relay_max_hops <= 0 or seq % max(1, params.relay_every) != 0:
        return message
    copies = relay_copies(heard, vehicle_id, t_s, seq, params.relay_max_hops, params.relay_max_age_s,
                          params.relay_budget_bytes)
    return msgspec.structs.replace(message, relayed=copies) if copies else message
