"""What the ground looks like: seeded, world-anchored textures and the sensor's own noise and shading.

Textures are periodic tiles fixed to the mission frame, so a scene stays put while the drone moves over it.
They are built once per seed (fractal noise by spectral synthesis) and cached: rendering only samples them.
Colours are chosen so land/water segmentation is a real task (grass, dry grass, bare soil, darker wet soil on
the shore against murky, sky-reflecting water), not a lookup of two flat colours.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from mock_autopilot.world.fractal import fractal_noise

TILE_PX = 512
"""Texture tile side [px]; the tile repeats every ``TILE_PX * TILE_RESOLUTION_M`` metres."""
TILE_RESOLUTION_M = 0.1
"""Ground size of one texture pixel [m]."""
NOISE_FRAMES = 8
"""Sensor-noise frames kept per (seed, image size); one is picked per frame."""
SENSOR_NOISE_SIGMA = 4.0
"""Standard deviation of the additive sensor noise [digital numbers out of 255]."""

WET_BAND_UNIT_M = 0.004
"""Resolution of the packed wet-band width [m per count]."""
WET_DARKENING_BGR = np.array([0.5, 0.45, 0.35], np.float32)
"""How much fully wet soil loses of each colour channel (B, G, R)."""

# BGR colours (0-255) of the ground classes.
_GRASS = np.array([55.0, 120.0, 80.0])
_DRY_GRASS = np.array([70.0, 150.0, 150.0])
_SOIL = np.array([70.0, 100.0, 130.0])
_WATER_DEEP = np.array([120.0, 95.0, 70.0])
_WATER_SKY = np.array([185.0, 165.0, 145.0])
WATER_TURBID_BGR = np.array([138.0, 124.0, 100.0], np.float32)
"""Shallow water over soil: silt-laden, grey-brown, only a little bluer than grey (the edge is a soft step)."""
TURBID_DEPTH_M = 0.25
"""Water shallower than this shows the turbid colour, fully at the shoreline and fading out at this depth."""
DEEP_DEPTH_M = 1.2
"""Water darkens with depth up to this depth, where it has lost ``DEEP_DARKENING`` of its brightness."""
DEEP_DARKENING = 0.3


STREAK_SPACING_M = 0.7
"""Distance between flow streaks across the current [m]."""
STREAK_WAVE_M = 3.0
"""Along the current the streaks wander with this wavelength [m]."""
STREAK_CONTRAST = 0.07
"""Brightness swing of the streaks on fast water (kept small: they are texture, not a second kind of ground)."""
STREAK_FULL_SPEED_MPS = 0.4
"""Water this fast shows the full streak contrast; still water shows none."""
STREAK_ZERO = 128.0
STREAK_SCALE = 127.0
"""The 8-bit streak tile holds ``STREAK_ZERO + STREAK_SCALE · pattern``."""


@lru_cache(maxsize=4)
def streak_tile(seed: int) -> NDArray[np.uint8]:
    """(TILE_PX, TILE_PX) streak pattern in [-1, 1], stored as ``STREAK_ZERO + STREAK_SCALE · value`` in 8 bits (a
    quarter of the memory a frame's warp reads), lines along the tile's x axis (periodic, so it tiles): the
    renderer turns it to run along the current. Lines ``STREAK_SPACING_M`` apart that wander every
    ``STREAK_WAVE_M``, with a seeded phase."""
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, 0x57EA])
    n = TILE_PX
    tile_m = n * TILE_RESOLUTION_M
    lines = round(tile_m / STREAK_SPACING_M)
    waves = round(tile_m / STREAK_WAVE_M)
    y, x = np.mgrid[0:n, 0:n] * (2.0 * math.pi / n)
    wander = 1.5 * np.sin(waves * x + rng.uniform(0.0, 2.0 * math.pi)) + 0.6 * fractal_noise(n, 2.0, rng)
    return np.rint(STREAK_ZERO + STREAK_SCALE * np.sin(lines * y + wander)).astype(np.uint8)


def streak_strength(speed_mps: NDArray[np.float32]) -> NDArray[np.float32]:
    """How much of the streak contrast water of this speed shows: none when still, all from the full speed on."""
    return (STREAK_CONTRAST * _smoothstep(speed_mps / np.float32(STREAK_FULL_SPEED_MPS))).astype(np.float32)


def streak_strength_of_speed(speed_mps: float) -> float:
    """:func:`streak_strength` of one speed, in the same float32 arithmetic without numpy's array machinery (the
    renderer asks once per frame)."""
    x = np.float32(speed_mps) / np.float32(STREAK_FULL_SPEED_MPS)
    x = min(max(x, np.float32(0.0)), np.float32(1.0))
    return float(np.float32(STREAK_CONTRAST) * (x * x * (np.float32(3.0) - np.float32(2.0) * x)))


def water_shading(depth_m: NDArray[np.float32]) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """(turbid weight, brightness) per pixel of water at ``depth_m``: shallow water near the shore is the turbid
    colour, deep water is darker (less light comes back from the bottom)."""
    turbid = 1.0 - _smoothstep(depth_m / TURBID_DEPTH_M)
    brightness = 1.0 - DEEP_DARKENING * _smoothstep((depth_m - TURBID_DEPTH_M) / (DEEP_DEPTH_M - TURBID_DEPTH_M))
    return turbid.astype(np.float32), brightness.astype(np.float32)


@dataclass(frozen=True)
class GroundTextures:
    """World-anchored texture tiles for one seed."""

    land_bgrw: NDArray[np.uint8]
    """(TILE_PX, TILE_PX, 4) dry land (grass, dry grass and soil patches) in BGR, and in the 4th channel the width
    of the wet shoreline band at each place in units of ``WET_BAND_UNIT_M`` (packed so one lookup fetches both)."""
    water_bgr: NDArray[np.uint8]
    """(TILE_PX, TILE_PX, 3) water: murky colour, sky reflections and ripples."""
    land_and_water: NDArray[np.uint16]
    """(TILE_PX, TILE_PX, 4) both tiles interleaved, 8 bytes per texel (land B, G, R, band width, water B, G, R, 0)
    seen as four 16-bit channels: one warp fetches a texel of each from one cache line (see ``render``)."""


@dataclass(frozen=True)
class SensorEffects:
    """Camera-fixed effects for one seed and image size."""

    gain_bgr: NDArray[np.float32]
    """(H, W, 3) multiplicative lighting: a sun gradient across the image and lens vignetting."""
    noise_up_bgr: NDArray[np.uint8]
    """(NOISE_FRAMES, H, W, 3) the positive part of additive Gaussian sensor noise [DN], rounded ..."""
    noise_down_bgr: NDArray[np.uint8]
    """... and its negative part, as a magnitude: a pixel's noise is one or the other, so adding the first and
    subtracting the second with 8-bit saturation gives the noisy pixel exactly (two 8-bit passes instead of a
    mixed 8/16-bit one)."""


def _smoothstep(x: NDArray[np.floating]) -> NDArray[np.floating]:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


@lru_cache(maxsize=4)
def ground_textures(seed: int) -> GroundTextures:
    """The texture tiles of one seed (about 0.1 s to build, then cached)."""
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, 0x7E47])
    n = TILE_PX
    patches = fractal_noise(n, 1.6, rng)
    dryness = fractal_noise(n, 1.4, rng)
    detail = fractal_noise(n, 0.9, rng)
    soil_w = _smoothstep((patches - 0.3) / 0.6)[..., None]
    dry_w = _smoothstep((dryness - 0.2) / 0.8)[..., None]
    land = (1.0 - soil_w) * ((1.0 - dry_w) * _GRASS + dry_w * _DRY_GRASS) + soil_w * _SOIL
    land *= (1.0 + 0.12 * detail)[..., None]

    sky = fractal_noise(n, 1.8, rng)
    yy, xx = np.mgrid[0:n, 0:n] * (2.0 * math.pi / n)
    ripple_dir = rng.uniform(0.0, math.pi)
    ripples = np.sin(37.0 * (np.cos(ripple_dir) * xx + np.sin(ripple_dir) * yy) + 2.0 * sky)
    sky_w = _smoothstep((sky + 1.0) / 3.0)[..., None] * 0.45
    water = (1.0 - sky_w) * _WATER_DEEP + sky_w * _WATER_SKY
    water *= (1.0 + 0.04 * ripples + 0.04 * detail)[..., None]

    wet_band = 0.25 + 0.35 * _smoothstep((fractal_noise(n, 1.7, rng) + 1.5) / 3.0)
    land_bgrw = np.clip(np.dstack([land, wet_band / WET_BAND_UNIT_M]), 0, 255).astype(np.uint8)
    water_bgr = np.clip(water, 0, 255).astype(np.uint8)
    texels = np.dstack([land_bgrw, water_bgr, np.zeros((n, n, 1), np.uint8)])
    return GroundTextures(land_bgrw=land_bgrw, water_bgr=water_bgr,
                          land_and_water=np.ascontiguousarray(texels).view(np.uint16))


@lru_cache(maxsize=16)
def sensor_effects(seed: int, width_px: int, height_px: int) -> SensorEffects:
    """Lighting gain and a bank of noise frames for one seed and image size (cached)."""
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, width_px, height_px, 0x5E75])
    y, x = np.mgrid[0:height_px, 0:width_px].astype(np.float64)
    x = (x + 0.5) / width_px - 0.5
    y = (y + 0.5) / height_px - 0.5
    sun = rng.uniform(0.0, 2.0 * math.pi)
    gradient = 0.14 * (math.cos(sun) * x + math.sin(sun) * y) / 0.5
    vignette = -0.25 * (x * x + y * y)
    gain = np.repeat((1.0 + gradient + vignette)[..., None], 3, axis=2).astype(np.float32)
    noise = np.rint(rng.normal(0.0, SENSOR_NOISE_SIGMA, (NOISE_FRAMES, height_px, width_px, 3)))
    return SensorEffects(gain_bgr=gain, noise_up_bgr=np.clip(noise, 0, 255).astype(np.uint8),
                         noise_down_bgr=np.clip(-noise, 0, 255).astype(np.uint8))
