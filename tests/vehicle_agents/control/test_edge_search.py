import numpy as np
import pytest

from mission_plan.geometry import footprint_side_m
from vehicle_agents.control.edge_search import (
    HOLD_S,
    MAX_REACH_FOOTPRINTS,
    SEARCH_SPEED_MPS,
    TOWARDS_LAND,
    TOWARDS_WATER,
    LastEdge,
    is_searching,
    launch_edge,
    reach_m,
    search_velocity,
)
from vehicle_agents.control.params import ControlParams, RosterEntry
from vehicle_agents.control.step import control_step, initial_memory
from vehicle_agents.control.types import OwnState
from vehicle_agents.perception.result import PerceptionResult

FOOTPRINT_M = float(footprint_side_m(10.0, 60.0))
# An edge running north through (12, 0), water to the west: normal (water -> land) east, tangent north.
EDGE = LastEdge(np.array([12.0, 0.0]), np.array([1.0, 0.0]), np.array([0.0, 1.0]), 0.0)
ONLY_LAND = PerceptionResult(False, 0.0, True, False, FOOTPRINT_M)
ONLY_WATER = PerceptionResult(False, 1.0, False, True, FOOTPRINT_M)
NO_FRAME = PerceptionResult.no_measurement(FOOTPRINT_M)


def _sweep(start_en_m: tuple[float, float], only_land: bool, only_water: bool, seconds: float,
           dt: float = 0.05) -> np.ndarray:
    """Positions of a drone that searches for ``seconds`` from ``start_en_m`` under the same flags every frame."""
    q = np.array(start_en_m, dtype=float)
    sign = 0.0
    path = [q.copy()]
    for k in range(int(seconds / dt)):
        v, sign = search_velocity(q, EDGE, sign, only_land, only_water, k * dt, FOOTPRINT_M)
        q = q + v * dt
        path.append(q.copy())
    return np.array(path)


@pytest.mark.parametrize(("only_land", "only_water", "first_way"), [(True, False, -1.0), (False, True, 1.0)])
def test_the_sweep_starts_towards_where_the_frame_says_the_edge_is(only_land: bool, only_water: bool,
                                                                   first_way: float) -> None:
    v, sign = search_velocity(np.array([12.0, 0.0]), EDGE, 0.0, only_land, only_water, 2.0, FOOTPRINT_M)
    assert sign == (TOWARDS_WATER if only_land else TOWARDS_LAND)
    assert v[0] == pytest.approx(first_way * SEARCH_SPEED_MPS)


def test_without_a_frame_the_sweep_heads_for_the_edge_line() -> None:
    _, sign = search_velocity(np.array([15.0, 0.0]), EDGE, 0.0, False, False, 2.0, FOOTPRINT_M)
    assert sign == TOWARDS_WATER
    _, sign = search_velocity(np.array([9.0, 0.0]), EDGE, 0.0, False, False, 2.0, FOOTPRINT_M)
    assert sign == TOWARDS_LAND


def test_a_misread_frame_can_never_carry_the_drone_away_from_the_last_edge() -> None:
    """Only land in every frame (turbid water read as soil): the drone goes to the water side as the frames say,
    turns back at the reach, comes back over the line and goes out again, ever wider, never further from it than the
    largest reach; along the edge it comes back to where it saw the edge."""
    path = _sweep((12.0, 6.0), only_land=True, only_water=False, seconds=120.0)
    across = path[:, 0] - 12.0
    assert np.max(np.abs(across)) <= MAX_REACH_FOOTPRINTS * FOOTPRINT_M + SEARCH_SPEED_MPS * 0.05 + 1e-9
    assert across.min() < -FOOTPRINT_M and across.max() >= 0.0  # back over the line after each turn, widening
    assert abs(path[-1, 1]) < 0.1  # back level with the last edge point along the edge


def test_frames_that_flip_turn_the_sweep_round_over_the_edge() -> None:
    """Land until it crosses x = 10 m, water beyond (the edge missed in every frame): it swings about x = 10 m."""
    q, sign = np.array([12.0, 0.0]), 0.0
    xs = []
    for k in range(400):
        over_land = q[0] > 10.0
        v, sign = search_velocity(q, EDGE, sign, over_land, not over_land, k * 0.05, FOOTPRINT_M)
        q = q + v * 0.05
        xs.append(q[0])
    assert 9.8 <= min(xs[40:]) and max(xs[40:]) <= 10.2


def test_without_frames_the_sweep_goes_from_bound_to_bound() -> None:
    path = _sweep((12.0, 0.0), only_land=False, only_water=False, seconds=120.0)
    across = path[:, 0] - 12.0
    assert across.min() < -FOOTPRINT_M and across.max() > FOOTPRINT_M
    assert np.max(np.abs(across)) <= MAX_REACH_FOOTPRINTS * FOOTPRINT_M + SEARCH_SPEED_MPS * 0.05 + 1e-9


def test_the_reach_grows_from_half_a_footprint_to_its_bound() -> None:
    assert reach_m(0.0, FOOTPRINT_M) == pytest.approx(0.5 * FOOTPRINT_M)
    assert reach_m(5.0, FOOTPRINT_M) > reach_m(1.0, FOOTPRINT_M)
    assert reach_m(1e6, FOOTPRINT_M) == pytest.approx(MAX_REACH_FOOTPRINTS * FOOTPRINT_M)


def test_the_search_waits_out_the_hold_without_a_frame_but_not_on_a_one_class_frame() -> None:
    assert is_searching(EDGE, True, 0.1)
    assert not is_searching(EDGE, False, HOLD_S - 0.05)
    assert is_searching(EDGE, False, HOLD_S + 0.05)


def _edge_north(position_en_m: np.ndarray) -> PerceptionResult:
    """A straight edge along x = 12 m (water west) seen from ``position_en_m``, within the footprint."""
    across = 12.0 - float(position_en_m[0])
    points = np.array([[across, y] for y in np.linspace(-4.0, 4.0, 9)])
    return PerceptionResult(True, 0.5, False, False, FOOTPRINT_M, np.array([across, 0.0]),
                            np.array([across - 2.0, 0.0]), np.array([across + 2.0, 0.0]),
                            np.array([1.0, 0.0]), np.array([0.0, 1.0]), points)


ROSTER = (RosterEntry(1, "boundary", "A", 0), RosterEntry(2, "boundary", "B", 0))


def _fly_losing_the_edge(mode: str, lost_view: PerceptionResult, seconds: float) -> np.ndarray:
    """A leading drone (encircling at 3 m/s) tracks the edge for 2 s, then sees only ``lost_view``."""
    params = ControlParams(mode=mode, roster=ROSTER, encircle_speed_mps=3.0, edge_point_tracking=True)
    memory = initial_memory("boundary", 1, params)
    q = np.array([12.5, 0.0])
    v = np.zeros(2)
    dt = 0.05
    path = []
    for k in range(int(seconds / dt)):
        t_s = k * dt
        view = _edge_north(q) if t_s < 2.0 else lost_view
        command, memory = control_step("boundary", memory, OwnState(q.copy(), 10.0, v.copy()), view, [], params, t_s)
        v = command.velocity_en_mps[:2]
        q = q + v * dt
        path.append(q.copy())
    return np.array(path)


@pytest.mark.parametrize("lost_view", [ONLY_LAND, ONLY_WATER, NO_FRAME], ids=["only-land", "only-water", "no-frame"])
def test_improved_leading_drone_that_loses_the_edge_stays_near_where_it_last_saw_it(lost_view: PerceptionResult) -> None:
    path = _fly_losing_the_edge("improved", lost_view, 60.0)
    last_seen = path[int(2.0 / 0.05) - 1]
    distance = np.hypot(*(path - last_seen).T)
    # Within the hold it keeps encircling (3 m/s for at most 1 s), then never beyond the sweep's reach plus that.
    assert distance.max() <= MAX_REACH_FOOTPRINTS * FOOTPRINT_M + 3.0 * HOLD_S + 1.0


def test_paper_mode_keeps_algorithm_1_as_printed() -> None:
    """The paper's drone only climbs: u_c carries it along the last tangent, as eq 8 says."""
    path = _fly_losing_the_edge("paper", ONLY_LAND, 20.0)
    assert path[-1, 1] - path[int(2.0 / 0.05), 1] > 15.0


# SPEC §4's launch site east of the flood: boundary column along x = 14 (A north, B south), the leader behind it.
LAUNCH_ROSTER = (
    RosterEntry(1, "boundary", "A", 0, pad_en_m=(14.0, 1.5)),
    RosterEntry(2, "boundary", "B", 0, pad_en_m=(14.0, -1.5)),
    RosterEntry(3, "leader", pad_en_m=(15.5, 0.0)),
)


def test_the_plan_puts_the_first_edge_through_the_pad_with_the_water_away_from_the_other_columns() -> None:
    edge = launch_edge(LAUNCH_ROSTER, 2, 0.5)
    assert edge is not None
    assert edge.point_en_m.tolist() == [14.0, -1.5]
    assert edge.normal_en == pytest.approx([1.0, 0.0])  # water (west) to land (east)
    assert edge.tangent_en == pytest.approx([0.0, 1.0])  # water on the left
    assert launch_edge(LAUNCH_ROSTER[:2], 2, 0.5) is None  # nobody behind the column: nothing to say
    assert launch_edge((RosterEntry(1, "boundary", "A", 0), RosterEntry(3, "leader")), 1, 0.5) is None


def test_a_drone_that_never_saw_the_edge_searches_on_the_flood_side_of_its_pad() -> None:
    """Only land from take-off (the flood's turbid edge missed at the image border): the drone heads west, towards
    the flood, instead of climbing in place; without pads in the roster it has nothing to search around."""
    for roster, moves_west in ((LAUNCH_ROSTER, True), ((RosterEntry(2, "boundary", "B", 0), RosterEntry(3, "leader")), False)):
        params = ControlParams(mode="improved", roster=roster, encircle_speed_mps=3.0, edge_point_tracking=True)
        memory = initial_memory("boundary", 2, params)
        q = np.array([14.0, -1.5])
        for k in range(60):
            command, memory = control_step("boundary", memory, OwnState(q.copy(), 10.0), ONLY_LAND, [], params, k * 0.05)
            q = q + command.velocity_en_mps[:2] * 0.05
        assert (q[0] < 11.5) == moves_west
        assert abs(q[1] + 1.5) < 0.1

