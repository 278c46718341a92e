import numpy as np

from vehicle_agents.control.follower import flock_offset_en_m, layer_fraction, layers_needed
from vehicle_agents.control.leader import polygon_area_centroid
from vehicle_agents.control.params import ControlParams, RosterEntry
from vehicle_agents.control.step import control_step, initial_memory
from vehicle_agents.control.types import NeighbourInfo, OwnState

ROSTER = (
    RosterEntry(1, "boundary", "A", 0),
    RosterEntry(2, "boundary", "B", 0),
    RosterEntry(3, "leader", has_gps=True),
    RosterEntry(4, "follower", layer=1, ref_id=1),
    RosterEntry(5, "follower", layer=2, ref_id=4),
)


def _nb(vid: int, role: str, pos: tuple[float, float], vel: tuple[float, float] = (0.0, 0.0), **extra: object) -> NeighbourInfo:
    return NeighbourInfo(vid, role, np.array(pos, dtype=float), np.array(vel, dtype=float), 10.0, **extra)  # type: ignore[arg-type]


def test_leader_tracks_mean_of_boundary_drones_with_feedforward() -> None:
    params = ControlParams(roster=ROSTER, k_leader_per_s=(0.5, 0.5))
    memory = initial_memory("leader", 3, params)
    heard = [_nb(1, "boundary", (10.0, 0.0), (0.0, 1.0)), _nb(2, "boundary", (-10.0, 4.0), (0.0, 1.0))]
    command, memory = control_step("leader", memory, OwnState(np.zeros(2), 10.0, has_gps=True), None, heard, params, 0.0)
    assert np.allclose(command.velocity_en_mps, [0.0, 0.5 * 2.0 + 1.0])  # eq 9
    assert memory.ring_radius_m is not None and memory.ring_radius_m > 9.0


def test_area_centroid_ignores_bunching() -> None:
    theta = np.concatenate([np.linspace(0.0, 0.5, 6), [2.0, 3.0, 4.0, 5.0]])
    pts = np.stack([10 * np.cos(theta), 10 * np.sin(theta)], axis=-1)
    assert np.linalg.norm(polygon_area_centroid(pts)) < np.linalg.norm(pts.mean(axis=0))


def test_follower_targets_a_point_between_leader_and_its_boundary_drone() -> None:
    params = ControlParams(roster=ROSTER, k_follower_per_s=(1.0, 1.0))
    memory = initial_memory("follower", 4, params)
    heard = [_nb(3, "leader", (0.0, 0.0), ring_radius_m=14.0), _nb(1, "boundary", (14.0, 0.0))]
    command, _ = control_step("follower", memory, OwnState(np.array([0.0, 0.0]), 10.0), None, heard, params, 0.0)
    # R = 14 m, footprint 11.5 m: one layer, fraction 1/2 -> target (7, 0), but the leader is 0 m away: beta of
    # followers only (leader is not a follower), so the command is K (target - q).
    assert np.allclose(command.velocity_en_mps, [7.0 if 7.0 < params.max_speed_mps else params.max_speed_mps, 0.0])


def test_layers_and_fractions() -> None:
    side = 11.547
    assert layers_needed(16.0, side, 0.9) == 1
    assert layers_needed(64.0, side, 0.9) == 6
    assert layer_fraction(1, 1) == 0.5
    assert abs(layer_fraction(1, 2) - 2 / 3) < 1e-12 and layer_fraction(2, 2) == 0.5
    # layers evenly spaced: radius of layer m = R (L + 1 - m)/(L + 1)
    L, R = 3, 40.0
    r = R
    for m in range(1, L + 1):
        r *= layer_fraction(m, L)
        assert abs(r - R * (L + 1 - m) / (L + 1)) < 1e-9


def test_unreleased_follower_waits_round_the_leader() -> None:
    params = ControlParams(roster=ROSTER, k_follower_per_s=(1.0, 1.0))
    memory = initial_memory("follower", 5, params)
    heard = [_nb(3, "leader", (0.0, 0.0), ring_radius_m=14.0), _nb(4, "follower", (30.0, 0.0))]
    command, _ = control_step("follower", memory, OwnState(np.array([0.0, 0.0]), 10.0), None, heard, params, 0.0)
    assert np.allclose(command.velocity_en_mps, flock_offset_en_m(0))


def test_improved_barrier_never_closes_below_minimum() -> None:
    params = ControlParams(mode="improved", roster=ROSTER, k_follower_per_s=(1.0, 1.0))
    memory = initial_memory("follower", 4, params)
    heard = [_nb(3, "leader", (0.0, 0.0), ring_radius_m=14.0), _nb(1, "boundary", (14.0, 0.0)),
             _nb(5, "follower", (7.5, 0.0))]
    q = np.array([5.0, 0.0])
    command, _ = control_step("follower", memory, OwnState(q, 10.0), None, heard, params, 0.0)
    towards = float(np.dot(command.velocity_en_mps, [1.0, 0.0]))
    assert towards <= params.safety_closing_rate_per_s * (2.5 - params.safety_min_distance_m) + 1e-9


def test_paper_mode_has_no_barrier_in_the_same_situation() -> None:
    params = ControlParams(mode="paper", roster=ROSTER, k_follower_per_s=(1.0, 1.0), separation_gain_mps=0.0)
    memory = initial_memory("follower", 4, params)
    heard = [_nb(3, "leader", (0.0, 0.0), ring_radius_m=14.0), _nb(1, "boundary", (14.0, 0.0)),
             _nb(5, "follower", (7.5, 0.0))]
    command, _ = control_step("follower", memory, OwnState(np.array([5.0, 0.0]), 10.0), None, heard, params, 0.0)
    assert float(np.dot(command.velocity_en_mps, [1.0, 0.0])) > 1.5
