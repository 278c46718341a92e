"""Placing the grey-water shore by colour along the split's boundary steps (pure function, synthetic frames: two flat
colours with texture on the land, the step at a known column)."""

from __future__ import annotations

import numpy as np

from vehicle_agents.perception.segmentation import perceive
from vehicle_agents.perception.boundary_steps import BoundarySteps, boundary_steps
from vehicle_agents.perception.shore import BAND_PX, COLOUR_SIGNS, colour_score, shore_along_steps

SIZE = 96
STEP_COLUMN = 50
"""Columns ``< STEP_COLUMN`` are water, the rest land."""
WATER_BGR = (100, 136, 160)
"""Tan, lighter and a little bluer in chromaticity than the soil (turbid floodwater)."""
SOIL_BGR = (70, 98, 128)


def turbid_shore(seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(3x3-median-like frame, its log grey, the spread of its three colour cues) with a vertical shore at
    ``STEP_COLUMN``: smooth water, textured soil."""
    rng = np.random.default_rng(seed)
    frame = np.empty((SIZE, SIZE, 3), np.float64)
    frame[:, :STEP_COLUMN] = WATER_BGR
    frame[:, STEP_COLUMN:] = SOIL_BGR
    frame[:, STEP_COLUMN:] *= 1.0 + 0.12 * rng.standard_normal((SIZE, SIZE - STEP_COLUMN, 1))
    frame += rng.normal(0.0, 1.5, frame.shape)
    image = np.clip(np.rint(frame), 0, 255).astype(np.uint8)
    return (image,) + cues_of(image)


def cues_of(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(log grey, std of chromaticity, saturation and log grey over the frame)."""
    pixels = image.astype(np.float64)
    log_grey = np.log(np.rint(pixels @ np.array([0.114, 0.587, 0.299])) + 1.0).astype(np.float32)
    total = pixels.sum(axis=2) + 9.0
    chromaticity = (pixels[..., 0] + 3.0) / total
    saturation = (pixels.max(axis=2) - pixels.min(axis=2)) / total
    return log_grey, np.array([chromaticity.std(), saturation.std(), log_grey.std()], np.float32)


def shore_of(coarse: np.ndarray, image: np.ndarray, log_grey: np.ndarray, spread: np.ndarray
             ) -> tuple[np.ndarray | None, BoundarySteps]:
    """The colour shore along ``coarse``'s steps, and those steps."""
    steps = boundary_steps(coarse)
    assert steps is not None
    score = colour_score(image, log_grey, COLOUR_SIGNS / (spread + np.float32(1e-9)))
    return shore_along_steps(steps, coarse, score), steps


def test_a_split_boundary_inside_the_water_is_moved_back_to_the_colour_step() -> None:
    for seed in range(4):
        image, log_grey, spread = turbid_shore(seed)
        for offset_px in (-4, -2, 0, 2):  # the split's boundary in the water, on the shore, in the land
            coarse = np.zeros((SIZE, SIZE), np.uint8)
            coarse[:, : STEP_COLUMN + offset_px] = 1
            points, _ = shore_of(coarse, image, log_grey, spread)
            assert points is not None and len(points) == SIZE
            assert np.all(np.abs(points[:, 0] - STEP_COLUMN) <= 1.0), (seed, offset_px, points[:, 0])
            assert abs(float(points[:, 0].mean()) - STEP_COLUMN) < 0.2
            assert np.array_equal(points[:, 1], np.arange(SIZE) + 0.5)  # each point stays on its step's row


def test_each_point_stays_on_its_step_line_within_the_band() -> None:
    image, log_grey, spread = turbid_shore(7)
    coarse = np.zeros((SIZE, SIZE), np.uint8)
    coarse[:, : STEP_COLUMN - 2] = 1
    coarse[40:44, 80:84] = 1  # a speck of "water" far out in the land: its steps are placed on their own lines
    points, steps = shore_of(coarse, image, log_grey, spread)
    assert points is not None and len(points) == len(steps.first_px)
    first = steps.first_px + 0.5
    along_x = steps.along_x
    assert np.array_equal(points[:along_x, 1], first[:along_x, 1])
    assert np.array_equal(points[along_x:, 0], first[along_x:, 0])
    moved = np.concatenate([points[:along_x, 0] - first[:along_x, 0], points[along_x:, 1] - first[along_x:, 1]])
    assert np.all(np.abs(moved) <= BAND_PX + 1.5)


def test_no_shore_when_colour_does_not_tell_the_sides_apart() -> None:
    image, _, _ = turbid_shore(3)
    image[:] = SOIL_BGR  # one colour everywhere: no step to place the shore on
    log_grey, spread = cues_of(image)
    coarse = np.zeros((SIZE, SIZE), np.uint8)
    coarse[:, :STEP_COLUMN] = 1
    assert shore_of(coarse, image, log_grey, spread)[0] is None
    image, log_grey, spread = turbid_shore(3)
    coarse[:, : SIZE - 2] = 1  # two columns of land at the frame's side: no land ring to measure its level on
    assert shore_of(coarse, image, log_grey, spread)[0] is None


def test_perceive_reports_the_colour_shore_where_the_grey_split_sits_in_the_water() -> None:
    """On a turbid shore the split's edge points lie inside the water (west of the step); the shore points
    perception gives for the report lie at the step, within a pixel."""
    for seed in range(3):
        image, _, _ = turbid_shore(seed)
        result = perceive(image, 10.0, 60.0, 0.0)
        assert result.has_edge and result.shore_points_en_m is not None
        step_east_m = (STEP_COLUMN - SIZE / 2) * result.ground_sample_m
        shore_error_m = abs(float(np.mean(result.shore_points_en_m[:, 0])) - step_east_m)
        edge_error_m = abs(float(np.mean(result.edge_points_en_m[:, 0])) - step_east_m)
        assert shore_error_m < result.ground_sample_m < edge_error_m
