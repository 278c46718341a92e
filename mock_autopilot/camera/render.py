"""Render what a drone's downward camera sees of the flood, with the ground-truth water mask (SPEC §3).

Each pixel centre is projected to the ground (nadir pinhole over flat ground, see ``camera/model.py``), the flood
model says whether it is water, and the pixel takes the world-anchored land or water texture. Land within a
seeded, varying distance of the water is darkened into a wet shoreline band; then lighting, a slight optical blur
and sensor noise are applied. Everything is vectorised and the textures are cached per seed, so a 128x128 frame
costs a fraction of a millisecond (see ``bench/camera_perception.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from comms.frames import yaw_ned_to_enu_rad
from mock_autopilot.camera.appearance import (
    NOISE_FRAMES,
    TILE_PX,
    TILE_RESOLUTION_M,
    WET_BAND_UNIT_M,
    WET_SOIL_BGR,
    ground_textures,
    sensor_effects,
)
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.world.flood_model import FloodModel

MIN_ALTITUDE_M = 0.1
"""Altitudes below this (a drone on its pad) are rendered as if from this height."""
MARGIN_PX = 8
"""Extra ring of pixels evaluated around the image so the wet band near the image border sees off-image water."""
_WET_STRENGTH = 0.85


@dataclass(frozen=True)
class RenderedFrame:
    """One camera frame and its truth."""

    image_bgr: NDArray[np.uint8]
    """(H, W, 3) BGR image; up = vehicle forward, right = vehicle right."""
    water_mask: NDArray[np.bool_]
    """(H, W) ground truth: True where the pixel centre is water."""
    ground_sample_m: float = 0.0
    """Ground distance of one pixel [m/px]; 0 for a blank frame."""


@lru_cache(maxsize=16)
def _pixel_grid(width_px: int, height_px: int, margin_px: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Pixel-centre offsets from the image centre [px]: (right, forward), for the image plus a margin."""
    cols = np.arange(-margin_px, width_px + margin_px, dtype=np.float64) + 0.5 - width_px / 2.0
    rows = np.arange(-margin_px, height_px + margin_px, dtype=np.float64) + 0.5 - height_px / 2.0
    right, down = np.meshgrid(cols, rows)
    return right, -down


def ground_points_en_m(
    camera: CameraModel, position_enu_m: ArrayLike, yaw_ned_rad: float, margin_px: int = 0
) -> NDArray[np.float64]:
    """(H+2m, W+2m, 2) ground (east, north) [m] under each pixel centre of the camera at ``position_enu_m``."""
    east, north, up = (float(v) for v in np.asarray(position_enu_m, dtype=float)[:3])
    gsd = camera.ground_sample_m(max(up, MIN_ALTITUDE_M))
    heading = yaw_ned_to_enu_rad(yaw_ned_rad)
    fwd_e, fwd_n = math.cos(heading), math.sin(heading)
    right_e, right_n = fwd_n, -fwd_e
    right, forward = _pixel_grid(camera.width_px, camera.height_px, margin_px)
    points = np.empty(right.shape + (2,))
    points[..., 0] = east + gsd * (right * right_e + forward * fwd_e)
    points[..., 1] = north + gsd * (right * right_n + forward * fwd_n)
    return points


def _blank(camera: CameraModel) -> RenderedFrame:
    return RenderedFrame(
        image_bgr=np.zeros((camera.height_px, camera.width_px, 3), np.uint8),
        water_mask=np.zeros((camera.height_px, camera.width_px), bool),
    )


def render_frame(
    flood: FloodModel,
    t_s: float,
    position_enu_m: ArrayLike,
    yaw_ned_rad: float,
    camera: CameraModel = CameraModel(),
    seed: int = 0,
) -> RenderedFrame:
    """The image the downward camera of a drone at ``position_enu_m`` (east, north, up [m]) sees at flood time ``t_s``.

    ``yaw_ned_rad`` is the PX4 yaw (clockwise from north). A non-finite pose gives an all-black frame with an
    all-land mask (a failed camera, which perception reports as no measurement); a height below
    ``MIN_ALTITUDE_M`` is rendered from that height. Deterministic for given arguments.
    """
    pos = np.asarray(position_enu_m, dtype=float).reshape(-1)
    if pos.size < 3 or not (np.all(np.isfinite(pos[:3])) and math.isfinite(yaw_ned_rad) and math.isfinite(t_s)):
        return _blank(camera)
    altitude_m = max(float(pos[2]), MIN_ALTITUDE_M)
    gsd = camera.ground_sample_m(altitude_m)
    m = MARGIN_PX
    h, w = camera.height_px, camera.width_px

    points = ground_points_en_m(camera, (pos[0], pos[1], altitude_m), yaw_ned_rad, margin_px=m)
    water_padded = np.asarray(flood.is_water(points, t_s), dtype=bool)
    water = water_padded[m : m + h, m : m + w]
    inner = points[m : m + h, m : m + w]

    textures = ground_textures(seed)
    map_x, map_y = _texture_maps(inner, (float(pos[0]), float(pos[1])))
    land = cv2.remap(textures.land_bgrw, map_x, map_y, cv2.INTER_NEAREST, borderMode=cv2.BORDER_WRAP)
    colour = land[..., :3]
    if water_padded.any():
        distance_px = cv2.distanceTransform((~water_padded).view(np.uint8), cv2.DIST_L2, 3)[m : m + h, m : m + w]
        band_px = land[..., 3].astype(np.float32) * np.float32(WET_BAND_UNIT_M / gsd)
        wetness = cv2.max(1.0 - distance_px / band_px, 0.0) * np.float32(_WET_STRENGTH)
        colour = cv2.blendLinear(colour, _wet_soil_image(w, h), 1.0 - wetness, wetness)
        water_tex = cv2.remap(textures.water_bgr, map_x, map_y, cv2.INTER_NEAREST, borderMode=cv2.BORDER_WRAP)
        colour = cv2.copyTo(water_tex, water.view(np.uint8), colour)

    effects = sensor_effects(seed, w, h)
    colour = cv2.GaussianBlur(colour, (3, 3), 0.6)
    shaded = cv2.multiply(colour, effects.gain_bgr, dtype=cv2.CV_32F)
    shaded = cv2.add(shaded, effects.noise_bgr[_noise_index(t_s, pos, seed)])
    image = np.clip(shaded, 0.0, 255.0).astype(np.uint8)
    return RenderedFrame(image_bgr=image, water_mask=water.copy(), ground_sample_m=gsd)



def _texture_maps(
    points_en_m: NDArray[np.float64], anchor_en_m: tuple[float, float]
) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """Texture-tile pixel coordinates of ground points; the tile repeats, so only the anchor's tile offset matters."""
    scale = 1.0 / TILE_RESOLUTION_M
    tile_m = TILE_PX * TILE_RESOLUTION_M
    origin_e = math.floor(anchor_en_m[0] / tile_m) * tile_m
    origin_n = math.floor(-anchor_en_m[1] / tile_m) * tile_m
    map_x = ((points_en_m[..., 0] - origin_e) * scale).astype(np.float32)
    map_y = ((-points_en_m[..., 1] - origin_n) * scale).astype(np.float32)
    return map_x, map_y


@lru_cache(maxsize=8)
def _wet_soil_image(width_px: int, height_px: int) -> NDArray[np.uint8]:
    return np.broadcast_to(np.asarray(WET_SOIL_BGR, np.uint8), (height_px, width_px, 3)).copy()


def _noise_index(t_s: float, position_enu_m: NDArray[np.float64], seed: int) -> int:
    """Which cached noise frame this frame uses: varies frame to frame, deterministic in the arguments."""
    key = int(round(t_s * 50.0)) * 7919 + int(round(position_enu_m[0] * 10.0)) * 104729
    key += int(round(position_enu_m[1] * 10.0)) * 1299709 + seed * 15485863
    return key % NOISE_FRAMES
