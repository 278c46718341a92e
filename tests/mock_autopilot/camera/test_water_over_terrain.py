"""The cheaper paths of the renderer: the hydro floods' 8-bit wet band and depth shading, and the shared passes that
must draw exactly what the plain ones drew (the geometric floods' frames may not change)."""

from __future__ import annotations

import math

import cv2
import numpy as np

from mock_autopilot.camera.appearance import ground_textures, sensor_effects
from mock_autopilot.camera.render import MARGIN_PX, _sample_land_and_water, _sample_tile
from mock_autopilot.camera.water_over_terrain import GAIN_FIXED_ONE, shade_by_depth, wet_shore_gain8

SIDE = 128
GSD_M = 0.09


def test_a_sliver_of_water_in_the_margin_wets_only_the_land_beside_it() -> None:
    textures = ground_textures(1)
    land = textures.land_bgrw[:SIDE, :SIDE]
    water = np.zeros((SIDE + 2 * MARGIN_PX, SIDE + 2 * MARGIN_PX), bool)
    water[-1, 60:63] = True  # three pixels at the outer edge of the margin, below the image
    gain = wet_shore_gain8(water, MARGIN_PX, np.ascontiguousarray(land), GSD_M)
    assert gain.shape == (SIDE, SIDE, 3) and gain.dtype == np.uint8
    assert np.all(gain[:100] == GAIN_FIXED_ONE), "land far from the water is dry"
    water[MARGIN_PX + 64:, :] = True  # the lower half of the image is water
    gain = wet_shore_gain8(water, MARGIN_PX, np.ascontiguousarray(land), GSD_M)
    assert np.all(gain[:50] == GAIN_FIXED_ONE)
    shore = gain[60:64].astype(float)
    assert shore.mean() < 0.9 * GAIN_FIXED_ONE, "land at the shore is darker"
    assert np.all(gain[62, :, 0] <= gain[62, :, 2]), "wet soil keeps more red than blue"


def test_depth_shading_is_turbid_at_the_shore_and_darker_when_deep() -> None:
    water = np.full((SIDE, SIDE, 3), (150, 120, 90), np.uint8)
    depth = np.tile(np.linspace(0.0, 1.5, SIDE, dtype=np.float32), (SIDE, 1))
    shaded = shade_by_depth(water, depth, None).astype(float)
    assert abs(shaded[:, 0].mean(axis=0) - (138, 124, 100)).max() <= 2, "the turbid colour at the shoreline"
    assert shaded[:, -1].sum(axis=1).mean() < 0.8 * water[0, 0].astype(float).sum(), "deep water is darker"
    streaks = np.full((SIDE, SIDE), 1.05, np.float32)
    assert shade_by_depth(water, depth, streaks)[:, -1].astype(float).mean() > shaded[:, -1].mean()


def test_interleaved_textures_pick_the_texels_two_warps_pick() -> None:
    textures = ground_textures(2)
    rng = np.random.default_rng(3)
    for _ in range(20):
        a, k = rng.uniform(-math.pi, math.pi), rng.uniform(0.3, 2.0)
        to_tile = np.array([[k * math.cos(a), -k * math.sin(a), rng.uniform(-600, 600)],
                            [k * math.sin(a), k * math.cos(a), rng.uniform(-600, 600)]])
        land, water = _sample_land_and_water(textures.land_and_water, to_tile, 160, 120)
        assert np.array_equal(land, _sample_tile(textures.land_bgrw, to_tile, 160, 120))
        assert np.array_equal(cv2.cvtColor(water, cv2.COLOR_BGRA2BGR), _sample_tile(textures.water_bgr, to_tile, 160, 120))


def test_noise_as_two_saturating_passes_equals_the_signed_noise() -> None:
    effects = sensor_effects(4, SIDE, SIDE)
    noise = effects.noise_up_bgr.astype(np.int16) - effects.noise_down_bgr.astype(np.int16)
    assert np.all((effects.noise_up_bgr == 0) | (effects.noise_down_bgr == 0))
    image = np.random.default_rng(5).integers(0, 256, (SIDE, SIDE, 3), dtype=np.uint8)
    image[:8] = 0
    image[-8:] = 255
    for i in range(noise.shape[0]):
        two_passes = cv2.subtract(cv2.add(image, effects.noise_up_bgr[i]), effects.noise_down_bgr[i])
        assert np.array_equal(two_passes, cv2.add(image, noise[i], dtype=cv2.CV_8U))
