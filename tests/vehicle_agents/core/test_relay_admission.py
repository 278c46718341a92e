"""Forged relayed copies: a key holder relaying another drone's state with a huge seq or a future time stamp
cannot silence it, in the onboard core and at the ground station; honest copies are never refused (pure)."""

from __future__ import annotations

import math

import numpy as np

from comms.messages import NeighbourState
from gcs.polygon.radio_node import GroundNode
from gcs.scenario import load_scenario
from vehicle_agents.autopilot_link import AutopilotTelemetry
from vehicle_agents.core.neighbours import Inbox, heard_after, replaces
from vehicle_agents.core.onboard import GroundOrder, OnboardInputs, OnboardPlan, initial_state, onboard_step
from vehicle_agents.core.relay_admission import CopyVerdict, admitted, copy_verdict, max_seq_advance
from vehicle_agents.core.telemetry import telemetry_batch
from vehicle_agents.flight_phase import Command, Phase, PhaseLimits

RATE_HZ = 20.0
DT_S = 1.0 / RATE_HZ
VICTIM, ATTACKER, HONEST_RELAY = 2, 3, 4
HUGE_SEQ = 10**9


def _state(sender: int, seq: int, t_s: float, hops: int = 0, x_m: float = 10.0,
           relayed: list[NeighbourState] | None = None) -> NeighbourState:
    return NeighbourState(sender_id=sender, role="boundary", seq=seq, t_s=t_s, position_en_m=(x_m, 0.0),
                          altitude_m=10.0, hops=hops, relayed=relayed or [])


def _forged(t_s: float, seq: int = HUGE_SEQ) -> NeighbourState:
    return _state(VICTIM, seq, t_s, hops=1, x_m=-90.0)


def _receiver() -> tuple[OnboardPlan, object]:
    scenario = load_scenario("circle")
    params = scenario.control_params("improved")
    assert params.relay_max_hops > 0 and params.state_rate_hz == scenario.control_rate_hz == RATE_HZ
    v = next(v for v in scenario.vehicles if v.vehicle_id == 1)
    plan = OnboardPlan((1,), (v.role,), ((v.pad_enu_m[0], v.pad_enu_m[1]),), (v.has_gps,), params,
                       PhaseLimits(takeoff_altitude_m=10.0))
    return plan, initial_state(plan, Phase.MISSION)


def _step(plan: OnboardPlan, state, t_s: float, states: list[NeighbourState]):
    tel = AutopilotTelemetry(position_ned_m=(0.0, 0.0, -10.0), velocity_ned_mps=(0.0, 0.0, 0.0), armed=True,
                             in_air=True, flight_mode="OFFBOARD", last_message_monotonic_s=5.0)
    inputs = OnboardInputs(t_s, telemetry_batch([tel], now_monotonic_s=5.01), [None], [Inbox(states=states)],
                           [GroundOrder(Command.START, 0.0, 0.0)])
    return onboard_step(plan, state, inputs)[1]


def test_a_forged_copy_with_a_huge_seq_does_not_silence_a_drone_heard_directly() -> None:
    plan, state = _receiver()
    for k in range(1, 41):
        t_s = k * DT_S
        carrier = _state(ATTACKER, k, t_s - DT_S, x_m=20.0, relayed=[_forged(t_s, HUGE_SEQ + k)])
        state = _step(plan, state, t_s, [_state(VICTIM, k, t_s - DT_S), carrier])
    filed = state.heard[0][VICTIM]
    assert (filed.seq, filed.hops, filed.position_en_m) == (40, 0, (10.0, 0.0))
    assert state.refused_copies == (40,)
    row = int(np.flatnonzero(state.tracks[0].ids == VICTIM)[0])
    np.testing.assert_allclose(state.tracks[0].x[row, :2], (10.0, 0.0), atol=0.5)


def test_a_forged_copy_does_not_silence_a_drone_heard_only_through_relays() -> None:
    """The forged copy comes first, when the receiver knows nothing of the victim; honest relays still get
    through, and once they do, the forger's later huge seqs are refused."""
    plan, state = _receiver()
    state = _step(plan, state, DT_S, [_state(ATTACKER, 1, 0.0, x_m=20.0, relayed=[_forged(DT_S)])])
    assert state.heard[0][VICTIM].seq == HUGE_SEQ  # nothing to check the first word against
    for k in range(2, 21):
        t_s = k * DT_S
        honest = _state(HONEST_RELAY, k, t_s - DT_S, x_m=15.0, relayed=[_state(VICTIM, k - 2, t_s - 2 * DT_S, hops=1)])
        carrier = _state(ATTACKER, k, t_s - DT_S, x_m=20.0, relayed=[_forged(t_s - 2 * DT_S, HUGE_SEQ + k)])
        state = _step(plan, state, t_s, [honest, carrier])
    filed = state.heard[0][VICTIM]
    assert (filed.seq, filed.position_en_m) == (18, (10.0, 0.0))
    assert state.refused_copies[0] >= 17


def test_copies_from_the_future_are_refused_and_counted_at_the_ground_station() -> None:
    node = GroundNode(np.array([0.0, 0.0, 2.0]), state_rate_hz=RATE_HZ)
    node.hear([_state(VICTIM, 5, 1.0)], 1.05)
    node.hear([_state(ATTACKER, 6, 1.05, relayed=[_forged(1000.0, 6)])], 1.1)
    assert node.heard[VICTIM].seq == 5 and node.refused_copies == 1
    node.hear([_state(VICTIM, 6, 1.05)], 1.1)
    assert node.heard[VICTIM].seq == 6


def test_the_origins_own_message_replaces_a_copy_and_copies_are_filed_by_origin_time() -> None:
    table, _ = heard_after({}, frozenset(), Inbox(states=[_forged(5.0)]), 1, 5.0, 3.0)
    table, _ = heard_after(table, frozenset(), Inbox(states=[_state(VICTIM, 7, 4.95)]), 1, 5.05, 3.0)
    assert table[VICTIM].seq == 7
    table, _ = heard_after({}, frozenset(), Inbox(states=[_forged(5.0)]), 1, 5.0, 3.0)
    table, _ = heard_after(table, frozenset(), Inbox(states=[_state(VICTIM, 7, 4.9, hops=1)]), 1, 5.05, 3.0)
    assert table[VICTIM].seq == HUGE_SEQ  # an older copy does not replace a newer one
    table, _ = heard_after(table, frozenset(), Inbox(states=[_state(VICTIM, 9, 5.05, hops=2)]), 1, 5.1, 3.0)
    assert table[VICTIM].seq == 9


def test_honest_copies_are_always_admitted() -> None:
    """An honest origin sends one state per period, so its seq never runs ahead of its time stamps; whatever the
    gap (losses) and the age of what is filed, its copies pass, including a copy a period ahead of a clock."""
    rng = np.random.default_rng(5)
    for _ in range(2000):
        filed_k, gap = int(rng.integers(0, 500)), int(rng.integers(0, 200))
        filed = _state(VICTIM, filed_k, filed_k * DT_S)
        copy = _state(VICTIM, filed_k + gap, (filed_k + gap) * DT_S, hops=int(rng.integers(1, 4)))
        now_s = copy.t_s + float(rng.uniform(-DT_S, 1.0))
        assert copy_verdict(copy, filed, now_s, RATE_HZ) is CopyVerdict.FILE
    assert max_seq_advance(1.0, RATE_HZ) == 32 and max_seq_advance(-1.0, RATE_HZ) == 2


def test_admission_counts_refusals_and_leaves_direct_states_alone() -> None:
    states = [_state(VICTIM, 2, 1.0), _forged(1.0), _forged(9.0, 3), _state(VICTIM, 3, 1.0, hops=1)]
    kept, refused = admitted(states, {VICTIM: _state(VICTIM, 1, 0.95)}, 1.0, RATE_HZ)
    assert refused == 2 and kept == [states[0], states[3]]
    assert admitted(states, {}, 1.0, 0.0) == (states, 0)


def test_copies_that_are_not_news_are_settled_without_changing_a_verdict() -> None:
    """Old copies, the filed entry met again and copies shared by several carriers are settled at once; forged
    ones (seq far ahead behind an old time stamp, or from the future) are still refused. Over random inboxes the
    result is the rule applied copy by copy (:func:`copy_verdict`, then newest wins)."""
    filed = _state(VICTIM, 10, 1.0)
    old_copy, again = _state(VICTIM, 8, 0.9, hops=1), _state(VICTIM, 10, 1.0, hops=2)
    seq_ahead, future = _state(VICTIM, HUGE_SEQ, 0.5, hops=1), _state(VICTIM, 9, 5.0, hops=1)
    states = [old_copy, filed, again, seq_ahead, old_copy, future]
    kept, refused = admitted(states, {VICTIM: filed}, 1.0, RATE_HZ)
    assert refused == 2 and kept == [old_copy, filed, again, old_copy]

    def one_by_one(inbox: list[NeighbourState], table: dict[int, NeighbourState], t_s: float) -> tuple[list, int]:
        reference, kept = dict(table), []
        for msg in inbox:
            current = reference.get(msg.sender_id)
            if msg.hops > 0 and copy_verdict(msg, current, t_s, RATE_HZ) is not CopyVerdict.FILE:
                continue
            kept.append(msg)
            if current is None or replaces(msg, current, math.inf):
                reference[msg.sender_id] = msg
        return kept, len(inbox) - len(kept)

    rng = np.random.default_rng(11)
    for _ in range(500):
        pool = [_state(int(rng.integers(2, 5)), int(rng.integers(0, 40)), float(rng.uniform(0.0, 2.2)),
                       hops=int(rng.integers(0, 3))) for _ in range(8)]
        inbox = [pool[int(i)] for i in rng.integers(0, len(pool), size=20)]
        table = {m.sender_id: m for m in pool[:2]}
        kept, refused = admitted(inbox, table, 2.0, RATE_HZ)
        expected_kept, expected_refused = one_by_one(inbox, table, 2.0)
        assert refused == expected_refused and list(kept) == expected_kept
