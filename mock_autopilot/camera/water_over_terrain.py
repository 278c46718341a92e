"""How water over terrain looks to the camera (the depth-shaded floods: the hydro model): shading by depth, flow
streaks, and the wet shore band computed for them at lower cost than for the geometric floods.

Shallow water at the shore is turbid grey-brown and the edge is a soft step, deeper water the texture's murky blue
and darker as it deepens, streaks run along the current below the drone; the three-channel work is done in 8-bit
fixed point (gains in steps of ``1/GAIN_FIXED_ONE``), so a frame costs a few integer passes.
"""

from __future__ import annotations

import math
from functools import lru_cache

import cv2
import numpy as np
from numpy.typing import NDArray

from mock_autopilot.camera.appearance import (
    STREAK_SCALE,
    STREAK_ZERO,
    TILE_PX,
    TILE_RESOLUTION_M,
    WATER_TURBID_BGR,
    WET_BAND_UNIT_M,
    WET_DARKENING_BGR,
    streak_strength_of_speed,
    streak_tile,
    water_shading,
)

DEPTH_LUT_STEP_M = 0.005
"""Depth resolution of the water shading table [m] (256 steps: to 1.275 m, deeper water shades as that)."""
GAIN_FIXED_ONE = 128.0
"""A gain of 1 in the 8-bit fixed-point gains of the depth shading and the hydro wet band (gains up to 255/128)."""
WET_FRACTION_STEPS = 64.0
"""Steps per band width of the hydro wet band's table (distance over band width, 8-bit)."""


def wet_shore_gain8(water_padded: NDArray[np.bool_], margin_px: int, land_bgrw: NDArray[np.uint8], gsd: float
                    ) -> NDArray[np.uint8]:
    """(H, W, 3) gain, in units of ``1/GAIN_FIXED_ONE``, darkening the land within the seeded wet band of the
    water in the padded mask ``water_padded`` (``margin_px`` around the image): ``render._wet_shore_factor`` for the
    depth-shaded floods, at a quarter of its cost. The distance to the water is taken at half resolution (every
    other pixel, then interpolated: the band is drawn to about a pixel, finer than the 2 m raster their shore comes
    from) and the gain is read in 8-bit fixed point from a table of the band fraction (``WET_FRACTION_STEPS`` steps
    per band width). Meant for the land only: the water is drawn over it. The other floods keep the
    full-resolution band in floating point, so their frames stay those of earlier runs."""
    m, h, w = margin_px, land_bgrw.shape[0], land_bgrw.shape[1]
    padded_h, padded_w = water_padded.shape
    w2 = water_padded
    water_half = (w2[0::2, 0::2] | w2[1::2, 0::2]) | (w2[0::2, 1::2] | w2[1::2, 1::2])  # a 2x2 block with water
    half = cv2.distanceTransform((~water_half).view(np.uint8), cv2.DIST_L2, 3)
    full = cv2.resize(half, (padded_w, padded_h), interpolation=cv2.INTER_LINEAR)[m : m + h, m : m + w]
    fraction = cv2.divide(full, cv2.extractChannel(land_bgrw, 3),
                          scale=WET_FRACTION_STEPS * 2.0 * gsd / WET_BAND_UNIT_M, dtype=cv2.CV_8U)
    return cv2.merge([cv2.LUT(fraction, table) for table in _wet_gain_tables()])


@lru_cache(maxsize=1)
def _wet_gain_tables() -> tuple[NDArray[np.uint8], ...]:
    """Per channel (B, G, R), the (1, 256) wet-band gain per band fraction step (distance / band width ·
    ``WET_FRACTION_STEPS``), in units of ``1/GAIN_FIXED_ONE``: fully wet at the shore, dry from one band width on.
    (Three one-channel tables: OpenCV looks a one-channel table up a few times faster than a three-channel one.)"""
    wetness = np.maximum(0.0, 1.0 - np.arange(256) / WET_FRACTION_STEPS)
    return tuple(np.rint((1.0 - wetness * float(k)) * GAIN_FIXED_ONE).astype(np.uint8).reshape(1, 256)
                 for k in WET_DARKENING_BGR)


def streaks(flow_mps: tuple[float, float], corner_en_m: NDArray[np.float64], shape: tuple[int, int], seed: int
             ) -> NDArray[np.float32] | None:
    """Per-pixel brightness gain of flow streaks over an image of ``shape`` (rows, columns) whose first two rows and
    columns of pixel centres lie at ``corner_en_m`` (2, 2, 2): the world-anchored streak tile turned to run along
    the current below the drone, with the contrast of its speed (one warp of a cached tile; a frame spans a few
    metres, over which the current hardly turns). None on still water (no streaks)."""
    speed = math.hypot(*flow_mps)
    strength = streak_strength_of_speed(speed)
    if strength <= 0.0:
        return None
    c, s = flow_mps[0] / speed, flow_mps[1] / speed
    origin = corner_en_m[0, 0]
    d_col = corner_en_m[0, 1] - origin
    d_row = corner_en_m[1, 0] - origin
    k = 1.0 / TILE_RESOLUTION_M
    tile_m = TILE_PX * TILE_RESOLUTION_M
    along0, across0 = (origin[0] * c + origin[1] * s) % tile_m, (-origin[0] * s + origin[1] * c) % tile_m
    to_tile = np.array([
        [k * (d_col[0] * c + d_col[1] * s), k * (d_row[0] * c + d_row[1] * s), k * along0],
        [k * (-d_col[0] * s + d_col[1] * c), k * (-d_row[0] * s + d_row[1] * c), k * across0],
    ])
    pattern = cv2.warpAffine(streak_tile(seed), to_tile, (shape[1], shape[0]),
                             flags=cv2.INTER_NEAREST | cv2.WARP_INVERSE_MAP, borderMode=cv2.BORDER_WRAP)
    k = strength / STREAK_SCALE
    return cv2.addWeighted(pattern, k, pattern, 0.0, 1.0 - k * STREAK_ZERO, dtype=cv2.CV_32F)


@lru_cache(maxsize=1)
def _depth_luts() -> tuple[NDArray[np.float32], NDArray[np.uint8], tuple[NDArray[np.uint8], ...]]:
    """Per depth step of ``DEPTH_LUT_STEP_M``: the gain on the water texture (one value for all three channels; as
    a float and in units of ``1/GAIN_FIXED_ONE``) and, per channel (B, G, R), the turbid colour added, so shading a
    frame is table lookups: ``water · gain + offset``."""
    depth = np.arange(256, dtype=np.float32) * DEPTH_LUT_STEP_M
    turbid, brightness = water_shading(depth)
    gain = (brightness * (1.0 - turbid)).astype(np.float32).reshape(1, 256)
    offsets = tuple(np.rint(turbid * float(c)).astype(np.uint8).reshape(1, 256) for c in WATER_TURBID_BGR)
    return gain, np.rint(gain * GAIN_FIXED_ONE).astype(np.uint8), offsets


def shade_by_depth(water_bgr: NDArray[np.uint8], depth_m: NDArray[np.float32],
                   streaks: NDArray[np.float32] | None) -> NDArray[np.uint8]:
    """Water over terrain: turbid grey-brown where shallow (the shoreline is a soft step, not a colour edge), the
    texture's murky blue beyond, darker as it deepens (``appearance.water_shading``, tabulated), with flow streaks
    (:func:`streaks`) on the clear part. The gain is the same on every channel, so it is looked up (and multiplied
    by the streaks) on one channel, then applied in 8-bit fixed point (``1/GAIN_FIXED_ONE`` steps, finer than a grey
    level over the water's colours), as is the turbid colour: the three-channel passes are integer ones."""
    gain, gain8_table, offsets = _depth_luts()
    step = cv2.convertScaleAbs(depth_m, alpha=1.0 / DEPTH_LUT_STEP_M)
    if streaks is None:
        gain8 = cv2.LUT(step, gain8_table)
    else:
        gain8 = cv2.convertScaleAbs(cv2.multiply(cv2.LUT(step, gain), streaks), alpha=GAIN_FIXED_ONE)
    shaded = cv2.multiply(water_bgr, cv2.merge([gain8, gain8, gain8]), scale=1.0 / GAIN_FIXED_ONE)
    return cv2.add(shaded, cv2.merge([cv2.LUT(step, table) for table in offsets]))
