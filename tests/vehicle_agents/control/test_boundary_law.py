import numpy as np
import pytest

from vehicle_agents.control.params import ControlParams, RosterEntry
from vehicle_agents.control.step import control_step, initial_memory
from vehicle_agents.control.types import NeighbourInfo, OwnState
from vehicle_agents.perception.result import PerceptionResult

def circle_perception(position_en_m: np.ndarray, altitude_m: float, radius_m: float, fov_deg: float = 60.0) -> PerceptionResult:
    """What an ideal camera over a water disc of ``radius_m`` at the origin reports (sampled on a 64x64 grid)."""
    side = 2.0 * altitude_m * np.tan(np.radians(fov_deg) / 2.0)
    n = 64
    axis = (np.arange(n) + 0.5) / n * side - side / 2.0
    ee, nn = np.meshgrid(axis, axis)
    water = (position_en_m[0] + ee) ** 2 + (position_en_m[1] + nn) ** 2 <= radius_m**2
    frac = float(water.mean())
    if frac == 0.0 or frac == 1.0:
        return PerceptionResult(False, frac, frac == 0.0, frac == 1.0, side)
    wc = np.array([ee[water].mean(), nn[water].mean()])
    lc = np.array([ee[~water].mean(), nn[~water].mean()])
    normal = (lc - wc) / np.linalg.norm(lc - wc)
    tangent = np.array([-normal[1], normal[0]])
    border = water & ~(np.roll(water, 1, 0) & np.roll(water, -1, 0) & np.roll(water, 1, 1) & np.roll(water, -1, 1))
    points = np.stack([ee[border], nn[border]], axis=-1)
    return PerceptionResult(True, frac, False, False, side, (wc + lc) / 2.0, wc, lc, normal, tangent, points)


ROSTER = (
    RosterEntry(1, "boundary", "A", 0),
    RosterEntry(2, "boundary", "A", 1),
    RosterEntry(3, "boundary", "B", 0),
)


def _fly(mode: str, start: tuple[float, float], radius_m: float, seconds: float) -> tuple[np.ndarray, list[float]]:
    params = ControlParams(mode=mode, roster=ROSTER, encircle_speed_mps=1.0)
    memory = initial_memory("boundary", 1, params)
    q = np.array(start, dtype=float)
    v = np.zeros(2)
    dt = 0.1
    radii = []
    for k in range(int(seconds / dt)):
        own = OwnState(q.copy(), 10.0, v.copy())
        command, memory = control_step("boundary", memory, own, circle_perception(q, 10.0, radius_m), [], params, k * dt)
        v = command.velocity_en_mps
        q = q + v * dt
        radii.append(float(np.hypot(*q)))
    return q, radii


@pytest.mark.parametrize("mode", ["paper", "improved"])
def test_lone_boundary_drone_settles_on_the_edge_and_circles_counter_clockwise(mode: str) -> None:
    q, radii = _fly(mode, (14.0, 0.0), 12.0, 20.0)
    assert abs(radii[-1] - 12.0) < (0.6 if mode == "paper" else 0.3)
    angle = np.degrees(np.arctan2(q[1], q[0]))
    assert 60.0 < angle < 120.0  # group A keeps water on its left: counter-clockwise at ~1 m/s (~95 deg in 20 s)


def test_group_b_circles_clockwise() -> None:
    params = ControlParams(roster=ROSTER)
    memory = initial_memory("boundary", 3, params)
    q = np.array([12.0, 0.0])
    command, _ = control_step("boundary", memory, OwnState(q, 10.0), circle_perception(q, 10.0, 12.0), [], params, 0.0)
    assert command.velocity_en_mps[1] < -0.5


def test_algorithm_1_climbs_when_only_water_or_only_land_and_returns_gently() -> None:
    params = ControlParams(roster=ROSTER)
    memory = initial_memory("boundary", 1, params)
    only_water = PerceptionResult(False, 1.0, False, True, 11.5)
    command, memory = control_step("boundary", memory, OwnState(np.zeros(2), 10.0), only_water, [], params, 0.0)
    assert command.velocity_enu_mps[2] > 0.5 and memory.climbing and memory.climb_events == 1
    only_land = PerceptionResult(False, 0.0, True, False, 11.5)
    command, memory = control_step("boundary", memory, OwnState(np.zeros(2), 12.0), only_land, [], params, 0.1)
    assert command.velocity_enu_mps[2] > 0.5 and memory.climb_events == 1
    q = np.array([12.0, 0.0])
    command, memory = control_step("boundary", memory, OwnState(q, 20.0), circle_perception(q, 20.0, 12.0), [], params, 0.2)
    assert -params.descent_speed_mps - 1e-9 <= command.velocity_enu_mps[2] < 0.0 and not memory.climbing


def test_paper_separation_pushes_boundary_neighbours_apart() -> None:
    params = ControlParams(roster=ROSTER, encircle_speed_mps=0.0)
    memory = initial_memory("boundary", 1, params)
    q = np.array([12.0, 0.0])
    nb = NeighbourInfo(2, "boundary", np.array([12.0, 2.0]), np.zeros(2), 10.0, group="A")
    alone, _ = control_step("boundary", memory, OwnState(q, 10.0), circle_perception(q, 10.0, 12.0), [], params, 0.0)
    pushed, _ = control_step("boundary", memory, OwnState(q, 10.0), circle_perception(q, 10.0, 12.0), [nb], params, 0.0)
    assert pushed.velocity_en_mps[1] < alone.velocity_en_mps[1] - 0.5


def test_stale_neighbours_and_bad_input_are_ignored() -> None:
    params = ControlParams(roster=ROSTER)
    memory = initial_memory("boundary", 1, params)
    q = np.array([12.0, 0.0])
    stale = NeighbourInfo(2, "boundary", np.array([12.0, 0.5]), np.zeros(2), 10.0, age_s=10.0, group="A")
    nan = NeighbourInfo(3, "boundary", np.array([np.nan, 0.0]), np.zeros(2), 10.0, group="B")
    with_them, _ = control_step("boundary", memory, OwnState(q, 10.0), circle_perception(q, 10.0, 12.0), [stale, nan], params, 0.0)
    without, _ = control_step("boundary", memory, OwnState(q, 10.0), circle_perception(q, 10.0, 12.0), [], params, 0.0)
    assert np.allclose(with_them.velocity_enu_mps, without.velocity_enu_mps)
    command, _ = control_step("boundary", memory, OwnState(q, 10.0), PerceptionResult.no_measurement(), [], params, 0.0)
    assert np.all(np.isfinite(command.velocity_enu_mps))


def test_the_drone_steers_on_the_edge_points_and_reports_the_colour_shore() -> None:
    """Where perception placed the shore again by colour, the reported points are those; the velocity is the one
    the split's edge points give, the same as without them."""
    params = ControlParams(mode="improved", roster=ROSTER, encircle_speed_mps=1.0, edge_point_tracking=True)
    q = np.array([12.0, 0.0])
    own = OwnState(q.copy(), 10.0, np.zeros(2))
    seen = circle_perception(q, 10.0, 12.0)
    shore = seen.edge_points_en_m + np.array([0.2, 0.0])
    with_shore = PerceptionResult(**{**seen.__dict__, "shore_points_en_m": shore})
    plain_command, plain = control_step("boundary", initial_memory("boundary", 1, params), own, seen, [], params, 0.0)
    command, memory = control_step("boundary", initial_memory("boundary", 1, params), own, with_shore, [], params, 0.0)
    assert np.array_equal(command.velocity_enu_mps, plain_command.velocity_enu_mps)
    assert np.allclose(memory.edge_points_en_m.mean(axis=0) - plain.edge_points_en_m.mean(axis=0), [0.2, 0.0],
                       atol=0.05)
