import math

import numpy as np
import pytest
from shapely.geometry import Point, Polygon

from gcs.polygon import caged_polygon, signed_area_m2

RADIUS_M = 16.0
FOOTPRINT_M = 11.547  # 2 * 10 m * tan(30 deg)
TRUTH = Point(0.0, 0.0).buffer(RADIUS_M, 256)


def iou(ring: np.ndarray) -> float:
    poly = Polygon(ring)
    return poly.intersection(TRUTH).area / poly.union(TRUTH).area


def ring_of_drones(n: int = 8, phase_rad: float = 0.3) -> np.ndarray:
    a = phase_rad + np.arange(n) * 2 * math.pi / n
    return np.stack([RADIUS_M * np.cos(a), RADIUS_M * np.sin(a)], axis=-1)


def edge_seen(drone: np.ndarray, rng: np.random.Generator, noise_m: float = 0.1) -> np.ndarray:
    theta = np.linspace(0.0, 2 * math.pi, 1000, endpoint=False)
    circle = np.stack([RADIUS_M * np.cos(theta), RADIUS_M * np.sin(theta)], axis=-1)
    inside = np.all(np.abs(circle - drone) <= FOOTPRINT_M / 2, axis=1)
    return circle[inside] + rng.normal(0.0, noise_m, (int(inside.sum()), 2))


@pytest.fixture
def scene() -> tuple[np.ndarray, list[np.ndarray]]:
    rng = np.random.default_rng(7)
    drones = ring_of_drones()
    return drones, [edge_seen(d, rng) for d in drones]


def test_a_perfect_octagon_on_the_circle_has_iou_about_0_90() -> None:
    ring = caged_polygon(ring_of_drones(), [])
    assert len(ring) == 8
    assert iou(ring) == pytest.approx(2 * math.sqrt(2) / math.pi, abs=1e-3)


def test_fusing_the_edge_points_the_cameras_see_reaches_0_97(scene) -> None:
    drones, edges = scene
    ring = caged_polygon(drones, edges)
    assert iou(ring) >= 0.97
    assert signed_area_m2(ring) > 0.0
    assert Polygon(ring).is_valid


def test_stray_edge_points_are_rejected(scene) -> None:
    drones, edges = scene
    rng = np.random.default_rng(3)
    noisy = [np.vstack([e, drones[i] + rng.uniform(-5.0, 5.0, (15, 2))]) for i, e in enumerate(edges)]
    clean_iou = iou(caged_polygon(drones, edges))
    assert iou(caged_polygon(drones, noisy)) >= clean_iou - 0.01


def test_a_wrong_drone_position_does_not_spoil_the_ring_when_its_camera_sees_the_edge(scene) -> None:
    drones, edges = scene
    wrong = drones.copy()
    wrong[2] += (25.0, -30.0)
    assert iou(caged_polygon(wrong, edges)) >= 0.97


def test_missing_drones_close_the_ring_over_the_gap(scene) -> None:
    drones, edges = scene
    gappy = drones.copy()
    gappy[[1, 5]] = np.nan
    edges = list(edges)
    edges[1] = np.zeros((0, 2))
    edges[5] = np.zeros((0, 2))
    ring = caged_polygon(gappy, edges[:7])  # a short list means "no points" for the rest
    assert 0.93 <= iou(ring) < 0.99


def test_ring_order_may_be_clockwise_or_scrambled(scene) -> None:
    drones, edges = scene
    reference = iou(caged_polygon(drones, edges))
    assert iou(caged_polygon(drones[::-1], edges[::-1])) == pytest.approx(reference, abs=1e-9)
    scrambled = [0, 4, 2, 6, 1, 5, 3, 7]
    assert iou(caged_polygon(drones[scrambled], [edges[i] for i in scrambled])) >= 0.97


def test_too_little_input_gives_an_empty_ring() -> None:
    assert caged_polygon(np.zeros((0, 2)), []).shape == (0, 2)
    assert caged_polygon([[0.0, 0.0], [1.0, 0.0]], []).shape == (0, 2)
    assert caged_polygon([[np.nan, np.nan]] * 4, []).shape == (0, 2)


def test_points_alone_without_a_drone_ring_use_their_hull() -> None:
    theta = np.linspace(0.0, 2 * math.pi, 400, endpoint=False)
    everything = np.stack([RADIUS_M * np.cos(theta), RADIUS_M * np.sin(theta)], axis=-1)
    ring = caged_polygon(np.zeros((0, 2)), [everything])
    assert iou(ring) >= 0.99


def test_a_non_convex_flood_is_followed_far_better_than_by_the_vertices() -> None:
    rng = np.random.default_rng(5)
    theta = np.linspace(0.0, 2 * math.pi, 4000, endpoint=False)
    radius = 16.0 * (1 + 0.2 * np.cos(3 * theta) + 0.1 * np.cos(5 * theta + 0.7))  # SPEC §3 non-convex flood
    edge = np.stack([radius * np.cos(theta), radius * np.sin(theta)], axis=-1)
    truth = Polygon(edge)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(edge, axis=0), axis=1))])
    drones = edge[np.searchsorted(arc, arc[-1] * (np.arange(8) + 0.3) / 8)]
    seen = []
    for d in drones:
        inside = np.all(np.abs(edge - d) <= FOOTPRINT_M / 2, axis=1)
        seen.append(edge[inside][::3] + rng.normal(0.0, 0.1, (len(edge[inside][::3]), 2)))

    def score(ring: np.ndarray) -> float:
        poly = Polygon(ring)
        return poly.intersection(truth).area / poly.union(truth).area

    assert score(drones) < 0.85
    assert score(caged_polygon(drones, seen)) >= 0.97
