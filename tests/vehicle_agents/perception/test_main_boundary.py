"""The shore is the frame's longest boundary; a blob of water in the land or of land in the water is not."""

from __future__ import annotations

import numpy as np

from vehicle_agents.control.vision_tracking import tracked_offset_en_m
from vehicle_agents.perception.main_boundary import main_boundary_kept
from vehicle_agents.perception.segmentation import perceive

SHAPE = (128, 128)


def vertical_shore(column_px: float, rows: np.ndarray) -> np.ndarray:
    return np.column_stack([np.full(len(rows), column_px), rows + 0.5])


def ring(centre_px: tuple[float, float], radius_px: float, count: int) -> np.ndarray:
    angle = np.linspace(0.0, 2.0 * np.pi, count, endpoint=False)
    return np.column_stack([centre_px[0] + radius_px * np.cos(angle), centre_px[1] + radius_px * np.sin(angle)])


def kept_points(points: np.ndarray) -> np.ndarray:
    kept = main_boundary_kept(points, SHAPE)
    return points if kept is None else points[kept]


def test_one_boundary_is_kept_whole() -> None:
    shore = vertical_shore(64.3, np.arange(128.0))
    assert main_boundary_kept(shore, SHAPE) is None


def test_a_blob_beside_the_shore_is_left_out() -> None:
    shore = vertical_shore(64.3, np.arange(128.0))
    blob = ring((100.0, 30.0), 5.0, 32)
    kept = kept_points(np.concatenate([blob, shore]))
    assert np.array_equal(kept, shore)


def test_a_shore_that_leaves_the_frame_and_comes_back_keeps_both_pieces() -> None:
    upper = vertical_shore(40.3, np.arange(0.0, 50.0))
    lower = vertical_shore(90.3, np.arange(70.0, 128.0))
    speck = ring((10.0, 110.0), 2.0, 12)
    points = np.concatenate([upper, speck, lower])
    kept = kept_points(points)
    assert np.array_equal(kept, np.concatenate([upper, lower]))


def test_a_boundary_broken_by_a_pixel_is_one_boundary() -> None:
    rows = np.delete(np.arange(128.0), [60, 61])
    shore = vertical_shore(64.3, rows)
    assert main_boundary_kept(shore, SHAPE) is None


def test_a_frame_with_a_water_blob_in_the_land_tracks_the_shore() -> None:
    """A blue patch in the grass (a puddle, a misread shadow) 3.5 m from the shore: neither the edge points nor the
    offset eq 5 tracks move towards it."""
    water, grass = (190, 130, 70), (60, 150, 80)
    image = np.empty((128, 128, 3), np.uint8)
    image[:, :60] = water
    image[:, 60:] = grass
    yy, xx = np.mgrid[0:128, 0:128]
    image[(xx - 104) ** 2 + (yy - 64) ** 2 <= 8 ** 2] = water
    noise = np.random.default_rng(3).normal(0.0, 2.0, image.shape)
    image = np.clip(image + noise, 0, 255).astype(np.uint8)

    result = perceive(image, 10.0, 60.0)

    ground_sample_m = result.ground_sample_m
    shore_east_m = (60.0 - 64.0) * ground_sample_m
    points = np.asarray(result.edge_points_en_m)
    assert result.has_edge and len(points) > 0
    assert np.all(np.abs(points[:, 0] - shore_east_m) < 2.0 * ground_sample_m)
    offset = tracked_offset_en_m(result, True)
    assert offset is not None and abs(offset[0] - shore_east_m) < 2.0 * ground_sample_m
