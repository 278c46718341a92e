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
    assert held == trust
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
    assert held == trust
    later = TrustLimits().hold_s + 0.2
    acted, trust = trusted_result(turned, np.array([10.0, 5.0]), later, held)
    assert acted is turned and trust.t_s == later


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
