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


def _smoothstep(x: NDArray[np.float32]) -> NDArray[np.float32]:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def _luminance(image: NDArray[np.float32]) -> NDArray[np.float32]:
    return cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)


def turbid_recolour(image: NDArray[np.float32], water_mask: NDArray[np.bool_], seed: int) -> NDArray[np.float32]:
    """Land becomes bare soil and water turbid tan, each keeping its own texture and shading (relative luminance)."""
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, 0x7B1E])
    turbid = TURBID_BGR * np.float32(rng.uniform(*TURBID_BRIGHTNESS))
    lum = _luminance(image)
    out = image.copy()
    land = ~water_mask
    if land.any():
        ratio = lum[land] / float(_luminance(SOIL_BGR.reshape(1, 1, 3))[0, 0])
        soil = SOIL_BGR[None, :] * ratio[:, None]
        out[land] = LAND_TO_SOIL * soil + (1.0 - LAND_TO_SOIL) * image[land]
    if water_mask.any():
        water_lum = lum[water_mask]
        relative = 1.0 + TURBID_TEXTURE * (water_lum / max(float(water_lum.mean()), 1.0) - 1.0)
        out[water_mask] = turbid[None, :] * relative[:, None]
    return out


@lru_cache(maxsize=4)
def _shadow_field(seed: int) -> NDArray[np.float32]:
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, 0xC10D])
    return fractal_noise(SHADOW_TILE_PX, 2.4, rng).astype(np.float32)


@lru_cache(maxsize=16)
def _shadow_threshold(seed: int, cover: float) -> float:
    """The field value above which a share ``cover`` of the ground is in shadow."""
    return float(np.quantile(_shadow_field(seed), 1.0 - cover))


def _sample_periodic(tile: NDArray[np.float32], points_en_m: NDArray[np.float64], resolution_m: float,
                     interpolation: int = cv2.INTER_LINEAR) -> NDArray[np.float32]:
    """A world-anchored periodic tile sampled at each ground point (tile x = east, tile y = south)."""
    n = tile.shape[0]
    map_x = np.mod(points_en_m[..., 0] / resolution_m, n).astype(np.float32)
    map_y = np.mod(-points_en_m[..., 1] / resolution_m, n).astype(np.float32)
    return cv2.remap(tile, map_x, map_y, interpolation, borderMode=cv2.BORDER_WRAP)


def cloud_shadow_gain(points_en_m: NDArray[np.float64], t_s: float, wind_en_mps: tuple[float, float], cover: float,
                      seed: int) -> NDArray[np.float32]:
    """(H, W, 3) light left by the cloud shadows at flood time ``t_s`` (the field drifts with the mean wind)."""
    if cover >= 1.0:
        return np.broadcast_to(1.0 - SHADOW_LOSS_BGR, points_en_m.shape[:2] + (3,)).astype(np.float32)
    drift = np.asarray(wind_en_mps, float) * t_s
    field = _sample_periodic(_shadow_field(seed), points_en_m - drift, SHADOW_RESOLUTION_M)
    shade = _smoothstep((field - _shadow_threshold(seed, cover)) / SHADOW_SOFT + 0.5)
    return 1.0 - shade[..., None] * SHADOW_LOSS_BGR[None, None, :]


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
    d2 = ((points_en_m - centre) ** 2).sum(axis=-1) / max(height_m, 0.1) ** 2
    envelope = np.exp(-0.5 * d2 / GLINT_SPREAD_RAD**2).astype(np.float32)
    h, w = envelope.shape
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, int(vehicle_id) & 0xFFFFFFFF,
                                 int(round(t_s * 1000.0)) & 0xFFFFFFFF, 0x611D])
    sparkle = rng.random(((h + 1) // 2, (w + 1) // 2), dtype=np.float32) ** 4
    sparkle = cv2.resize(sparkle, (w, h), interpolation=cv2.INTER_NEAREST)
    return GLINT_DN * envelope * (0.4 + 2.0 * sparkle)


@lru_cache(maxsize=4)
def _debris_tile(seed: int) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """(colour (N, N, 3), opacity (N, N)) of the debris over one periodic tile."""
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
    return colour, alpha


def debris_layer(points_en_m: NDArray[np.float64], seed: int) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """(colour (H, W, 3), opacity (H, W)) of the floating debris at each ground point."""
    colour, alpha = _debris_tile(seed)
    return (_sample_periodic(colour, points_en_m, DEBRIS_RESOLUTION_M, cv2.INTER_NEAREST),
            _sample_periodic(alpha, points_en_m, DEBRIS_RESOLUTION_M, cv2.INTER_NEAREST))
