"""A boundary drone doubts one frame that contradicts a recent edge (it holds its track), and believes a
contradiction that lasts."""

from __future__ import annotations

import numpy as np

from vehicle_agents.perception.edge_trust import NO_TRUST, EdgeTrust, TrustLimits, edge_point_en_m, trusted_result
from vehicle_agents.perception.result import PerceptionResult

FOOTPRINT_M = 11.5


def edge_frame(across_m: float) -> PerceptionResult:
    """An edge ``across_m`` east of the drone, water to the west (normal pointing east, water to land)."""
    points = np.column_stack([np.full(9, across_m), np.linspace(-4.0, 4.0, 9)])
    return PerceptionResult(
        has_edge=True, water_fraction=0.5, only_land=False, only_water=False, footprint_side_m=FOOTPRINT_M,
        midpoint_offset_en_m=np.array([across_m, 0.0]), water_centroid_en_m=np.array([across_m - 3.0, 0.0]),
        land_centroid_en_m=np.array([across_m + 3.0, 0.0]), edge_normal_en=np.array([1.0, 0.0]),
        edge_tangent_en=np.array([0.0, 1.0]), edge_points_en_m=points)


def turned_frame(turn_rad: float, across_m: float = 0.5) -> PerceptionResult:
    """The edge of :func:`edge_frame` turned by ``turn_rad`` about the point below the drone."""
    c, s = np.cos(turn_rad), np.sin(turn_rad)
    rotation = np.array([[c, -s], [s, c]])
    frame = edge_frame(across_m)
    return PerceptionResult(
        has_edge=True, water_fraction=0.5, only_land=False, only_water=False, footprint_side_m=FOOTPRINT_M,
        midpoint_offset_en_m=rotation @ frame.midpoint_offset_en_m, edge_normal_en=rotation @ frame.edge_normal_en,
        edge_tangent_en=rotation @ frame.edge_tangent_en, edge_points_en_m=frame.edge_points_en_m @ rotation.T)


def one_class(only_water: bool) -> PerceptionResult:
    return PerceptionResult(has_edge=False, water_fraction=1.0 if only_water else 0.0, only_land=not only_water,
                            only_water=only_water, footprint_side_m=FOOTPRINT_M)


def seen_at(trust: EdgeTrust, t_s: float) -> EdgeTrust:
    own = np.array([10.0, 5.0])
    _, trust = trusted_result(edge_frame(0.5), own, t_s, trust)
    return trust


def test_the_edge_point_is_placed_from_the_own_position_across_the_normal() -> None:
    assert edge_point_en_m(edge_frame(1.5), np.array([10.0, 5.0])) == (11.5, 5.0)


def test_a_consistent_edge_is_acted_on_and_remembered() -> None:
    trust = seen_at(NO_TRUST, 0.0)
    frame = edge_frame(0.8)
    acted, trust = trusted_result(frame, np.array([10.2, 6.0]), 0.1, trust)
    assert acted is frame
    assert trust.edge_en_m == (11.0, 6.0) and trust.t_s == 0.1


def test_one_frame_with_the_edge_metres_away_is_doubted_then_believed_when_it_lasts() -> None:
    trust = seen_at(NO_TRUST, 0.0)
    jumped = edge_frame(4.5)
    acted, held = trusted_result(jumped, np.array([10.0, 5.0]), 0.1, trust)
    assert not acted.has_edge and not acted.only_land and not acted.only_water, "hold: no edge, no climb"
    assert (held.edge_en_m, held.t_s) == (trust.edge_en_m, trust.t_s)
    later = TrustLimits().hold_s + 0.2
    acted, trust = trusted_result(jumped, np.array([10.0, 5.0]), later, held)
    assert acted is jumped and trust.t_s == later


def test_an_edge_turned_far_from_the_last_is_doubted_then_believed_when_it_lasts() -> None:
    """A cloud shadow's edge across turbid water read as a second shore turns the fitted edge by tens of degrees
    within one frame; the edge point alone stays within the jump limit, so the direction must be checked too."""
    trust = seen_at(NO_TRUST, 0.0)
    turned = turned_frame(np.radians(75.0))
    acted, held = trusted_result(turned, np.array([10.0, 5.0]), 0.1, trust)
    assert not acted.has_edge and not acted.only_land and not acted.only_water
    assert (held.edge_en_m, held.t_s) == (trust.edge_en_m, trust.t_s)
    later = TrustLimits().hold_s + 0.2
    acted, trust = trusted_result(turned, np.array([10.0, 5.0]), later, held)
    assert acted is turned and trust.t_s == later


def test_an_edge_drifting_with_the_wind_is_never_believed_however_long_it_is_seen() -> None:
    """A cloud shadow's edge read as the shore, drifting at 3 m/s across the drone's frames for 2 s: every frame is
    doubted; the shore seen again afterwards is acted on at once."""
    trust = seen_at(NO_TRUST, 0.0)
    own = np.array([10.0, 5.0])
    for k in range(1, 21):
        t_s = 0.1 * k
        acted, trust = trusted_result(edge_frame(2.5 + 3.0 * t_s), own, t_s, trust)
        assert not acted.has_edge, f"the drifting edge was obeyed at {t_s:.1f} s"
    shore = edge_frame(0.6)
    acted, trust = trusted_result(shore, own, 2.1, trust)
    assert acted is shore and trust.t_s == 2.1 and trust.candidate_en_m is None


def test_a_trusted_frame_between_misread_ones_keeps_the_edge() -> None:
    trust = seen_at(NO_TRUST, 0.0)
    own = np.array([10.0, 5.0])
    for k in range(1, 31):
        t_s = 0.1 * k
        frame = edge_frame(6.0) if k % 2 else edge_frame(0.5)
        acted, trust = trusted_result(frame, own, t_s, trust)
        assert acted.has_edge == (k % 2 == 0), f"frame at {t_s:.1f} s"


def test_an_edge_seen_long_after_the_last_trusted_one_is_taken_when_near_it() -> None:
    """A drone that has seen no edge it trusts for 3.5 s (searching, climbing) takes an edge 4 m from its last one:
    the trusted edge's allowance has widened with its age past the hold."""
    trust = seen_at(NO_TRUST, 0.0)
    moved = edge_frame(4.5)
    assert trusted_result(moved, np.array([10.0, 5.0]), 3.5, trust)[0] is moved


def test_a_misread_frame_held_at_its_first_look_is_held_at_its_second() -> None:
    """Frames come at half the control rate, so the same frame is judged twice, 50 ms apart; within the hold the
    limit does not widen, so a frame just past it stays doubted."""
    trust = seen_at(NO_TRUST, 0.0)
    own = np.array([10.0, 5.0])
    just_past = edge_frame(0.5 + TrustLimits().max_jump_m + 0.12)
    first, trust = trusted_result(just_past, own, 0.10, trust)
    second, trust = trusted_result(just_past, own, 0.15, trust)
    assert not first.has_edge and not second.has_edge


def test_an_edge_turning_as_a_bend_does_is_acted_on() -> None:
    trust = seen_at(NO_TRUST, 0.0)
    bend = turned_frame(np.radians(20.0))
    acted, trust = trusted_result(bend, np.array([10.0, 5.0]), 0.1, trust)
    assert acted is bend and trust.t_s == 0.1
    allowed = TrustLimits().max_turn_rad + TrustLimits().turn_rate_radps * 0.9
    wider = turned_frame(np.radians(20.0) + allowed - 0.05)
    assert trusted_result(wider, np.array([10.0, 5.0]), 1.0, trust)[0] is wider


def test_only_land_while_the_edge_should_be_in_view_is_doubted() -> None:
    trust = seen_at(NO_TRUST, 0.0)
    acted, _ = trusted_result(one_class(only_water=False), np.array([10.0, 5.0]), 0.3, trust)
    assert not acted.only_land and not acted.has_edge


def test_only_water_far_from_the_last_edge_or_long_after_it_is_acted_on() -> None:
    trust = seen_at(NO_TRUST, 0.0)
    frame = one_class(only_water=True)
    far = np.array([10.5 - 0.5 * FOOTPRINT_M, 5.0])
    assert trusted_result(frame, far, 0.3, trust)[0] is frame
    assert trusted_result(frame, np.array([10.0, 5.0]), 5.0, trust)[0] is frame


def test_without_a_trusted_edge_every_result_is_acted_on() -> None:
    for frame in (edge_frame(4.0), one_class(True), one_class(False), PerceptionResult.no_measurement(FOOTPRINT_M)):
        assert trusted_result(frame, np.zeros(2), 1.0, NO_TRUST)[0] is frame
    assert trusted_result(None, np.zeros(2), 1.0, NO_TRUST) == (None, NO_TRUST)
