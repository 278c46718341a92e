"""The onboard core, pure: one batched call equals N single-drone calls, and the neighbour rule is one rule."""

from __future__ import annotations

import math

import numpy as np

from comms.messages import FLAG_LEAVING, NeighbourState, decode, encode
from gcs.scenario import load_scenario
from vehicle_agents.autopilot_link import AutopilotTelemetry
from vehicle_agents.core.neighbours import Inbox, heard_after
from vehicle_agents.core.onboard import (
    GroundOrder,
    OnboardInputs,
    OnboardPlan,
    initial_state,
    onboard_step,
)
from vehicle_agents.core.telemetry import TelemetryBatch, telemetry_batch
from vehicle_agents.flight_phase import Action, Command, Phase, PhaseLimits

START = GroundOrder(Command.START, 0.0, 0.0)


def _plan(ids: tuple[int, ...] | None = None) -> OnboardPlan:
    scenario = load_scenario("circle")
    params = scenario.control_params("improved")
    chosen = [v for v in scenario.vehicles if ids is None or v.vehicle_id in ids]
    return OnboardPlan(tuple(v.vehicle_id for v in chosen), tuple(v.role for v in chosen),
                       tuple((v.pad_enu_m[0], v.pad_enu_m[1]) for v in chosen), tuple(v.has_gps for v in chosen),
                       params, PhaseLimits(takeoff_altitude_m=10.0))


def _hovering(plan: OnboardPlan, rng: np.random.Generator) -> TelemetryBatch:
    n = len(plan)
    tel = [AutopilotTelemetry(position_ned_m=(float(rng.normal()), float(rng.normal()), -10.0),
                              velocity_ned_mps=(float(rng.normal()), float(rng.normal()), 0.0), armed=True,
                              in_air=True, flight_mode="OFFBOARD", last_message_monotonic_s=5.0) for _ in range(n)]
    return telemetry_batch(tel, now_monotonic_s=5.01)


def _row(batch: TelemetryBatch, i: int) -> TelemetryBatch:
    return TelemetryBatch(*(getattr(batch, f)[i:i + 1] for f in TelemetryBatch.__dataclass_fields__))


def test_one_batched_call_equals_one_call_per_drone() -> None:
    plan = _plan()
    n = len(plan)
    rng = np.random.default_rng(1)
    batch_state = initial_state(plan, Phase.MISSION)
    singles = [OnboardPlan((plan.vehicle_ids[i],), (plan.roles[i],), (plan.pads_en_m[i],), (plan.has_gps[i],),
                           plan.params, plan.limits) for i in range(n)]
    single_states = [initial_state(p, Phase.MISSION) for p in singles]
    messages: list[NeighbourState | None] = [None] * n
    for k in range(30):
        t_s = 0.05 * k
        telemetry = _hovering(plan, rng)
        inbox = [Inbox(states=[m for j, m in enumerate(messages) if m is not None and j != i]) for i in range(n)]
        out, batch_state = onboard_step(plan, batch_state, OnboardInputs(t_s, telemetry, [None] * n, inbox, [START] * n))
        for i in range(n):
            single_out, single_states[i] = onboard_step(
                singles[i], single_states[i], OnboardInputs(t_s, _row(telemetry, i), [None], [inbox[i]], [START]))
            assert single_out.actions[0] is out.actions[i] is Action.FLY
            np.testing.assert_array_equal(single_out.velocity_setpoint_ned_mps[0], out.velocity_setpoint_ned_mps[i])
            assert single_out.state_messages[0] == out.state_messages[i]
        messages = [decode(NeighbourState, encode(m)) for m in out.state_messages]
    assert any(np.linalg.norm(out.velocity_setpoint_ned_mps, axis=1) > 0.1)


def _state(sender: int, seq: int, t_s: float, flags: int = 0) -> NeighbourState:
    return NeighbourState(sender_id=sender, role="boundary", seq=seq, t_s=t_s, position_en_m=(1.0, 0.0),
                          altitude_m=10.0, flags=flags)


def test_a_neighbour_counts_until_its_message_is_older_than_the_timeout() -> None:
    heard, departed = heard_after({}, frozenset(), Inbox(states=[_state(2, 1, 10.0)]), 1, 10.0, 3.0)
    heard, departed = heard_after(heard, departed, Inbox(), 1, 12.9, 3.0)
    assert list(heard) == [2]
    heard, departed = heard_after(heard, departed, Inbox(), 1, 13.1, 3.0)
    assert heard == {}


def test_newest_seq_wins_and_leaving_or_a_vanished_token_removes_until_it_returns() -> None:
    heard, departed = heard_after({}, frozenset(), Inbox(states=[_state(2, 5, 1.0), _state(2, 4, 0.9)]), 1, 1.0, 3.0)
    assert heard[2].seq == 5
    heard, departed = heard_after(heard, departed, Inbox(states=[_state(2, 6, 1.1, FLAG_LEAVING)]), 1, 1.1, 3.0)
    assert heard == {} and departed == {2}
    heard, departed = heard_after(heard, departed, Inbox(states=[_state(2, 7, 1.2)]), 1, 1.2, 3.0)
    assert heard == {}
    heard, departed = heard_after(heard, departed, Inbox(states=[_state(2, 8, 1.3)], returned_ids=[2]), 1, 1.3, 3.0)
    assert list(heard) == [2]
    heard, departed = heard_after(heard, departed, Inbox(departed_ids=[2]), 1, 1.4, 3.0)
    assert heard == {} and departed == {2}


def test_a_restarted_sender_is_heard_again_despite_its_lower_seq() -> None:
    heard, _ = heard_after({}, frozenset(), Inbox(states=[_state(2, 500, 10.0)]), 1, 10.0, 3.0)
    heard, _ = heard_after(heard, frozenset(), Inbox(states=[_state(2, 1, 13.5)]), 1, 13.5, 3.0)
    assert heard[2].seq == 1


def test_stop_leaves_with_a_leaving_message_and_silence_means_no_message() -> None:
    plan = _plan((1, 9))
    state = initial_state(plan, Phase.MISSION)
    telemetry = _hovering(plan, np.random.default_rng(3))
    silent = TelemetryBatch(**{**{f: getattr(telemetry, f) for f in TelemetryBatch.__dataclass_fields__},
                               "link_silence_s": np.array([0.01, math.nan])})
    out, state = onboard_step(plan, state, OnboardInputs(1.0, silent, [None, None], [Inbox(), Inbox()],
                                                         [START, START], stop=[True, False]))
    assert out.actions[0] is Action.EXIT and state.phases[0] is Phase.DONE
    assert out.state_messages[0] is not None and out.state_messages[0].has(FLAG_LEAVING)
    assert out.state_messages[1] is None


def test_a_boundary_drone_holds_its_altitude_on_one_only_land_frame_after_an_edge() -> None:
    """Algorithm 1 climbs on only land; one such frame right after an edge in view is doubted (no climb), a run of
    them longer than the hold is believed (climb)."""
    from vehicle_agents.perception.result import PerceptionResult

    plan = _plan()
    i = plan.roles.index("boundary")
    single = OnboardPlan((plan.vehicle_ids[i],), ("boundary",), (plan.pads_en_m[i],), (plan.has_gps[i],),
                         plan.params, plan.limits)
    telemetry = _row(_hovering(plan, np.random.default_rng(3)), i)
    points = np.column_stack([np.full(9, 1.0), np.linspace(-4.0, 4.0, 9)])
    edge = PerceptionResult(
        has_edge=True, water_fraction=0.4, only_land=False, only_water=False, footprint_side_m=11.5,
        midpoint_offset_en_m=np.array([1.0, 0.0]), water_centroid_en_m=np.array([-2.0, 0.0]),
        land_centroid_en_m=np.array([4.0, 0.0]), edge_normal_en=np.array([1.0, 0.0]),
        edge_tangent_en=np.array([0.0, 1.0]), edge_points_en_m=points)
    land = PerceptionResult(has_edge=False, water_fraction=0.0, only_land=True, only_water=False,
                            footprint_side_m=11.5)
    state = initial_state(single, Phase.MISSION)
    out, state = onboard_step(single, state, OnboardInputs(0.0, telemetry, [edge], [Inbox()], [START]))
    out, state = onboard_step(single, state, OnboardInputs(0.1, telemetry, [land], [Inbox()], [START]))
    assert out.velocity_setpoint_ned_mps[0, 2] >= 0.0, "one doubtful frame: no climb (NED z up is negative)"
    assert not state.memories[0].climbing
    out, state = onboard_step(single, state, OnboardInputs(2.0, telemetry, [land], [Inbox()], [START]))
    assert out.velocity_setpoint_ned_mps[0, 2] < 0.0 and state.memories[0].climbing, "a lasting one: climb"
