import numpy as np

from vehicle_agents.control.params import ControlParams, RosterEntry
from vehicle_agents.control.ring_spacing import ring_neighbours, spacing_velocity
from vehicle_agents.control.types import NeighbourInfo


def _nb(vid: int, pos: tuple[float, float], vel: tuple[float, float] = (0.0, 0.0)) -> NeighbourInfo:
    return NeighbourInfo(vid, "boundary", np.array(pos), np.array(vel), 10.0)


def test_ring_order_runs_from_b_leader_through_a_to_a_leader() -> None:
    roster = tuple(RosterEntry(i + 1, "boundary", g, r) for i, (g, r) in enumerate([("A", 0), ("A", 1), ("B", 0), ("B", 1)]))
    assert ControlParams(roster=roster).ring_order() == (3, 4, 2, 1)


def test_neighbours_open_chain_and_closed_ring_and_skip_lost() -> None:
    order = (3, 4, 2, 1)
    heard = {i: _nb(i, (0.0, 0.0)) for i in (3, 4, 2, 1)}
    prev, nxt = ring_neighbours(1, order, heard, closed=False)
    assert prev is not None and prev.vehicle_id == 2 and nxt is None
    prev, nxt = ring_neighbours(1, order, heard, closed=True)
    assert nxt is not None and nxt.vehicle_id == 3
    del heard[2]
    prev, _ = ring_neighbours(1, order, heard, closed=True)
    assert prev is not None and prev.vehicle_id == 4


def test_consensus_moves_towards_the_larger_gap() -> None:
    t = np.array([1.0, 0.0])
    v = spacing_velocity(np.array([0.0, 0.0]), t, _nb(1, (-2.0, 0.0)), _nb(2, (6.0, 0.0)), 1.0)
    assert np.allclose(v, [2.0, 0.0])
    even = spacing_velocity(np.array([0.0, 0.0]), t, _nb(1, (-4.0, 0.0), (1.0, 0.0)), _nb(2, (4.0, 0.0), (1.0, 0.0)), 1.0)
    assert np.allclose(even, [1.0, 0.0])  # equal gaps: just keep the neighbours' pace


def test_chain_converges_to_equal_gaps() -> None:
    x = np.array([0.0, 1.0, 1.5, 2.0, 10.0])
    for _ in range(400):
        v = np.zeros_like(x)
        for i in range(1, len(x) - 1):
            v[i] = spacing_velocity(np.array([x[i], 0.0]), np.array([1.0, 0.0]), _nb(0, (x[i - 1], 0.0)), _nb(0, (x[i + 1], 0.0)), 0.8)[0]
        x = x + 0.1 * v
    assert np.allclose(np.diff(x), 2.5, atol=0.01)


def test_neighbour_on_the_wrong_side_gives_a_negative_gap() -> None:
    # the "next" drone is behind me along the tangent (order scrambled at launch): move back past it
    t = np.array([1.0, 0.0])
    v = spacing_velocity(np.array([0.0, 0.0]), t, _nb(1, (-3.0, 0.0)), _nb(2, (-1.0, 0.0)), 1.0)
    assert v[0] < 0.0
