"""The world's own hard cases for a water/land camera, drawn over a rendered frame (float BGR, 0-255).

- Turbid water beside brown soil: silt-laden floodwater is tan, a little lighter and yellower than the wet soil it
  covers, and the land beside it is bare soil; the scene keeps its texture and shading, only the colours go.
- Cloud shadows: a seeded, world-anchored field (a few tens of metres across, like cumulus shadows at noon) that
  drifts with the mean wind, dimming the ground and tinting it towards the blue skylight.
- Sun glint: the sun's mirror image on rippled water, centred where a ray reflected off a flat surface would point
  at the sun (``h tan(zenith)`` from the nadir, towards the sun), spread by the wave slopes, sparkling frame to frame.
- Floating debris: branches, litter and foam on the water, world-anchored (seeded).
"""

from __future__ import annotations

import math
from functools import lru_cache

import cv2
import numpy as np
from numpy.typing import NDArray

from mock_autopilot.world.fractal import fractal_noise

SOIL_BGR = np.array([72.0, 98.0, 128.0], np.float32)
"""Bare brown soil beside turbid water (B, G, R)."""
TURBID_BGR = np.array([96.0, 132.0, 156.0], np.float32)
"""Silt-laden water: tan, lighter and yellower than the soil (B, G, R); scaled per seed by ``TURBID_BRIGHTNESS``."""
TURBID_BRIGHTNESS = (0.92, 1.08)
"""Range of the seeded brightness of the turbid water relative to ``TURBID_BGR``."""
TURBID_TEXTURE = 0.5
"""Share of the water texture's relative contrast kept in turbid water (silt hides the sky's reflections)."""
LAND_TO_SOIL = 0.8
"""How far the land's colour goes to bare soil (the rest keeps a trace of vegetation)."""
SHADOW_TILE_PX = 256
SHADOW_RESOLUTION_M = 1.0
"""The cloud-shadow field repeats every 256 m."""
SHADOW_SOFT = 0.2
"""Width of the shadow's penumbra in units of the field's standard deviation."""
SHADOW_LOSS_BGR = np.array([0.38, 0.46, 0.5], np.float32)
"""Light lost in full shadow per channel (less blue: the shadow is lit by the blue sky)."""
SUN_ZENITH_DEG = (8.0, 28.0)
"""Range of the seeded sun zenith angle (late morning to early afternoon in summer)."""
GLINT_SPREAD_RAD = 0.12
"""Angular spread of the glint (wave slopes)."""
GLINT_DN = 150.0
"""Brightness added at the glint's centre before sparkle [DN]."""
DEBRIS_TILE_PX = 512
DEBRIS_RESOLUTION_M = 0.1
DEBRIS_PIECES = 420
"""Debris pieces per 51.2 m tile (a few per cent of the water covered)."""


_SOIL_LUMINANCE = float(0.114 * SOIL_BGR[0] + 0.587 * SOIL_BGR[1] + 0.299 * SOIL_BGR[2])


def _luminance(image: NDArray[np.float32]) -> NDArray[np.float32]:
    return cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)


def turbid_recolour(image: NDArray[np.float32], water_mask: NDArray[np.bool_], seed: int) -> NDArray[np.float32]:
    """Land becomes bare soil and water turbid tan, each keeping its own texture and shading (relative luminance)."""
    turbid = TURBID_BGR * np.float32(_turbid_brightness(seed))
    lum = _luminance(image)
    soil = cv2.merge([lum * np.float32(LAND_TO_SOIL * c / _SOIL_LUMINANCE) for c in SOIL_BGR])
    land = cv2.addWeighted(image, 1.0 - LAND_TO_SOIL, soil, 1.0, 0.0)
    if not water_mask.any():
        return land
    m8 = water_mask.view(np.uint8)
    relative = lum * np.float32(TURBID_TEXTURE / max(cv2.mean(lum, mask=m8)[0], 1.0)) + np.float32(1.0 - TURBID_TEXTURE)
    water = cv2.merge([relative * np.float32(c) for c in turbid])
    return cv2.copyTo(water, m8, land)


@lru_cache(maxsize=16)
def _turbid_brightness(seed: int) -> float:
    return float(np.random.default_rng([int(seed) & 0xFFFFFFFF, 0x7B1E]).uniform(*TURBID_BRIGHTNESS))


@lru_cache(maxsize=4)
def _shadow_field(seed: int) -> NDArray[np.float32]:
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, 0xC10D])
    return fractal_noise(SHADOW_TILE_PX, 2.4, rng).astype(np.float32)


@lru_cache(maxsize=16)
def _shadow_threshold(seed: int, cover: float) -> float:
    """The field value above which a share ``cover`` of the ground is in shadow."""
    return float(np.quantile(_shadow_field(seed), 1.0 - cover))


def _sample_periodic(tile: NDArray[np.float32], points_en_m: NDArray[np.float64], resolution_m: float,
                     interpolation: int = cv2.INTER_LINEAR, shift_en_m: tuple[float, float] = (0.0, 0.0)
                     ) -> NDArray[np.float32]:
    """A world-anchored periodic tile sampled at each ground point minus ``shift_en_m`` (tile x = east, tile y =
    south). Coordinates are taken relative to the tile period holding the first point, so they stay small; the tile
    wraps. One affine ``cv2.transform`` builds the (x, y) map for ``cv2.remap``."""
    period_m = tile.shape[0] * resolution_m
    shift = np.asarray(shift_en_m, float)
    offset = np.floor((points_en_m[0, 0] - shift) / period_m) * period_m + shift
    k = 1.0 / resolution_m
    # Tile y runs south: one period is added so the map lands inside the tile (wrapping far outside it is slow).
    to_tile = np.array([[k, 0.0, -k * offset[0]], [0.0, -k, k * offset[1] + tile.shape[0]]])
    xy = cv2.transform(points_en_m.reshape(-1, 1, 2), to_tile).astype(np.float32).reshape(points_en_m.shape)
    return cv2.remap(tile, xy, None, interpolation, borderMode=cv2.BORDER_WRAP)


def cloud_shadow_gain(points_en_m: NDArray[np.float64], t_s: float, wind_en_mps: tuple[float, float], cover: float,
                      seed: int) -> NDArray[np.float32]:
    """(H, W, 3) light left by the cloud shadows at flood time ``t_s`` (the field drifts with the mean wind)."""
    if cover >= 1.0:
        return np.broadcast_to(1.0 - SHADOW_LOSS_BGR, points_en_m.shape[:2] + (3,)).astype(np.float32)
    drift = (float(wind_en_mps[0]) * t_s, float(wind_en_mps[1]) * t_s)
    field = _sample_periodic(_shadow_field(seed), points_en_m, SHADOW_RESOLUTION_M, shift_en_m=drift)
    scale = 1.0 / SHADOW_SOFT
    x = cv2.min(cv2.max(cv2.addWeighted(field, scale, field, 0.0, 0.5 - _shadow_threshold(seed, cover) * scale), 0.0),
                1.0)
    shade = cv2.multiply(cv2.multiply(x, x), cv2.addWeighted(x, -2.0, x, 0.0, 3.0))  # smoothstep
    return cv2.merge([cv2.addWeighted(shade, -float(loss), shade, 0.0, 1.0) for loss in SHADOW_LOSS_BGR])


@lru_cache(maxsize=16)
def sun_direction(seed: int) -> tuple[float, float]:
    """(zenith [rad], azimuth clockwise from north [rad]) of the mission's sun."""
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, 0x5A11])
    return math.radians(rng.uniform(*SUN_ZENITH_DEG)), rng.uniform(0.0, 2.0 * math.pi)


def glint_layer(points_en_m: NDArray[np.float64], position_en_m: tuple[float, float], height_m: float, t_s: float,
                seed: int, vehicle_id: int) -> NDArray[np.float32]:
    """(H, W) brightness [DN] the sun's glint adds where the ground is water."""
    zenith, azimuth = sun_direction(seed)
    reach = height_m * math.tan(zenith)
    centre = np.array([position_en_m[0] + reach * math.sin(azimuth), position_en_m[1] + reach * math.cos(azimuth)])
    h, w = points_en_m.shape[:2]
    reach_m = 4.0 * GLINT_SPREAD_RAD * max(height_m, 0.1)
    corners = points_en_m[[0, 0, -1, -1], [0, -1, 0, -1]]
    half_diagonal = 0.5 * float(np.hypot(*(corners[0] - corners[3])))
    if float(np.hypot(*(points_en_m[h // 2, w // 2] - centre))) > half_diagonal + reach_m:
        return np.zeros((h, w), np.float32)  # the glint is out of view
    offset = cv2.transform(points_en_m.reshape(-1, 1, 2), np.array([[1.0, 0.0, -centre[0]], [0.0, 1.0, -centre[1]]]))
    east, north = cv2.split(offset.astype(np.float32).reshape(h, w, 2))
    d2 = cv2.add(cv2.multiply(east, east), cv2.multiply(north, north))
    envelope = cv2.exp(d2 * np.float32(-0.5 / (GLINT_SPREAD_RAD * max(height_m, 0.1)) ** 2))
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, int(vehicle_id) & 0xFFFFFFFF,
                                 int(round(t_s * 1000.0)) & 0xFFFFFFFF, 0x611D])
    sparkle = rng.random(((h + 1) // 2, (w + 1) // 2), dtype=np.float32)
    sparkle = cv2.multiply(sparkle, sparkle)
    sparkle = cv2.resize(cv2.multiply(sparkle, sparkle), (w, h), interpolation=cv2.INTER_NEAREST)
    return cv2.multiply(envelope, cv2.addWeighted(sparkle, 2.0 * GLINT_DN, sparkle, 0.0, 0.4 * GLINT_DN))


@lru_cache(maxsize=4)
def _debris_tile(seed: int) -> NDArray[np.float32]:
    """(N, N, 4) colour (B, G, R) and opacity of the debris over one periodic tile."""
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, 0xDEB2])
    n = DEBRIS_TILE_PX
    colour = np.zeros((n, n, 3), np.float32)
    alpha = np.zeros((n, n), np.float32)
    kinds = (np.array([40.0, 55.0, 70.0]), np.array([215.0, 220.0, 220.0]), np.array([60.0, 90.0, 110.0]))
    for _ in range(DEBRIS_PIECES):
        kind = int(rng.integers(len(kinds)))
        bgr = tuple(float(c) for c in kinds[kind] * rng.uniform(0.85, 1.15))
        centre = (int(rng.integers(n)), int(rng.integers(n)))
        length = rng.uniform(0.15, 0.6) / DEBRIS_RESOLUTION_M
        axes = (max(1, int(length / 2)), max(1, int(length * rng.uniform(0.15, 0.6) / 2)))
        angle = float(rng.uniform(0.0, 180.0))
        for dx in (-n, 0, n):
            for dy in (-n, 0, n):
                at = (centre[0] + dx, centre[1] + dy)
                cv2.ellipse(colour, at, axes, angle, 0, 360, bgr, -1)
                cv2.ellipse(alpha, at, axes, angle, 0, 360, 1.0, -1)
    return cv2.merge([*cv2.split(colour), alpha])


def debris_layer(points_en_m: NDArray[np.float64], seed: int) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """(colour (H, W, 3), opacity (H, W)) of the floating debris at each ground point."""
    layer = _sample_periodic(_debris_tile(seed), points_en_m, DEBRIS_RESOLUTION_M, cv2.INTER_NEAREST)
    return layer[..., :3], np.ascontiguousarray(layer[..., 3])
