"""Render what a drone's downward camera sees of the flood, with the ground-truth water mask (SPEC §3).

Each pixel centre is projected to the ground (nadir pinhole over locally flat ground at the height above ground a
rangefinder would read, see ``camera/model.py`` and ``world/ground.py``), the flood model says whether it is water,
and the pixel takes the world-anchored land or water texture; a flood that knows its depth (the hydro model) shades
its water by depth (turbid at the shore, darker where deep) and draws streaks along its flow. Land within a
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

from comms.camera_projection import pixel_to_ground, project_pixels
from comms.frames import yaw_ned_to_enu_rad
from mock_autopilot.camera.appearance import (
    NOISE_FRAMES,
    TILE_PX,
    TILE_RESOLUTION_M,
    WET_BAND_UNIT_M,
    WET_DARKENING_BGR,
    ground_textures,
    sensor_effects,
)
from mock_autopilot.camera.imaging_conditions import FrameInputs, apply_imaging
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.camera.water_over_terrain import GAIN_FIXED_ONE, shade_by_depth, streaks, wet_shore_gain8
from mock_autopilot.world.flood_model import FloodModel
from mock_autopilot.world.ground import height_above_ground_m
from mission_plan.imaging import ImagingSpec

MIN_ALTITUDE_M = 0.1
"""Altitudes below this (a drone on its pad) are rendered as if from this height."""
MARGIN_PX = 8
"""Extra ring of pixels evaluated around the image so the wet band near the image border sees off-image water."""
_PIXEL_CENTRES = np.array([[1.0, 0.0, 0.5], [0.0, 1.0, 0.5], [0.0, 0.0, 1.0]])
"""Pixel index (column, row) -> continuous image coordinates of its centre."""
_WET_DARKENING_SCALAR = tuple(float(k) for k in WET_DARKENING_BGR) + (0.0,)
_ONE_BGR = (1.0, 1.0, 1.0, 0.0)
_CORNER_ROWS = np.array([0, 1, MARGIN_PX, MARGIN_PX + 1])
"""Rows (and columns) of the padded pixel grid whose ground points a depth-shaded level frame needs: the grid's
first two (the depth raster's warp) and the image's first two (the streaks)."""


@dataclass(frozen=True)
class RenderedFrame:
    """One camera frame and its truth."""

    image_bgr: NDArray[np.uint8]
    """(H, W, 3) BGR image; up = vehicle forward, right = vehicle right."""
    water_mask: NDArray[np.bool_]
    """(H, W) ground truth: True where the pixel centre is water."""
    ground_sample_m: float = 0.0
    """Ground distance of one pixel [m/px]; 0 for a blank frame."""


@lru_cache(maxsize=64)
def _knows_depth(model_type: type) -> bool:
    """Whether a flood model class is a ``flood_model.DepthField`` (checked once per class: a Protocol check is slow, and
    one with a data member cannot be made on a class)."""
    return all(callable(getattr(model_type, name, None)) for name in ("depth_m", "depth_on_affine_grid_m"))


@lru_cache(maxsize=16)
def _pixel_grid(width_px: int, height_px: int, margin_px: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Pixel-centre offsets from the image centre [px]: (right, forward), for the image plus a margin."""
    cols = np.arange(-margin_px, width_px + margin_px, dtype=np.float64) + 0.5 - width_px / 2.0
    rows = np.arange(-margin_px, height_px + margin_px, dtype=np.float64) + 0.5 - height_px / 2.0
    right, down = np.meshgrid(cols, rows)
    return right, -down


@lru_cache(maxsize=16)
def _pixel_axes(width_px: int, height_px: int, margin_px: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Pixel-centre offsets from the image centre [px] along a row (right) and down a column (forward), for the
    image plus a margin: a level camera's ground point is an affine function of the two, so it is one outer sum."""
    right, forward = _pixel_grid(width_px, height_px, margin_px)
    return np.ascontiguousarray(right[0]), np.ascontiguousarray(forward[:, 0])


def ground_points_en_m(
    camera: CameraModel, position_enu_m: ArrayLike, yaw_ned_rad: float, margin_px: int = 0,
    tilt_rad: tuple[float, float] = (0.0, 0.0),
) -> NDArray[np.float64]:
    """(H+2m, W+2m, 2) ground (east, north) [m] under each pixel centre of the camera at ``position_enu_m``.

    ``tilt_rad`` is the body's (roll, pitch) [rad]: the camera is fixed to the body, so a tilted drone looks off
    nadir (:mod:`mock_autopilot.camera.tilt`); level, the projection is the nadir map of SPEC §3.
    """
    east, north, up = (float(v) for v in np.asarray(position_enu_m, dtype=float)[:3])
    if tilt_rad != (0.0, 0.0):
        to_ground = _tilted_homography(camera, up, yaw_ned_rad, tilt_rad)
        if to_ground is None:
            raise ValueError("camera sees the horizon: no ground projection")
        right, forward = _pixel_grid(camera.width_px, camera.height_px, margin_px)
        return project_pixels(to_ground, right + camera.width_px / 2.0, camera.height_px / 2.0 - forward) + np.array(
            [east, north])
    right, forward = _pixel_axes(camera.width_px, camera.height_px, margin_px)
    return _level_points(camera, (east, north, up), yaw_ned_rad, right, forward)


def _level_points(camera: CameraModel, position_enu_m: tuple[float, float, float], yaw_ned_rad: float,
                  right: NDArray[np.float64], forward: NDArray[np.float64]) -> NDArray[np.float64]:
    """(len(forward), len(right), 2) ground points of a level camera at the pixel-centre offsets ``right`` (along a
    row) and ``forward`` (up a column) [px]: the whole grid, or some of its rows and columns in the same arithmetic
    (a flood that warps its depth raster only needs the grid's corner)."""
    east, north, up = position_enu_m
    gsd = camera.ground_sample_m(max(up, MIN_ALTITUDE_M))
    heading = yaw_ned_to_enu_rad(yaw_ned_rad)
    fwd_e, fwd_n = math.cos(heading), math.sin(heading)
    right_e, right_n = fwd_n, -fwd_e
    points = np.empty((forward.size, right.size, 2))
    for axis, origin, along_right, along_forward in ((0, east, right_e, fwd_e), (1, north, right_n, fwd_n)):
        along_row = right * (gsd * along_right)
        down_column = forward * (gsd * along_forward)
        np.add(along_row[None, :] + down_column[:, None], origin, out=points[..., axis])
    return points


def _tilted_homography(camera: CameraModel, height_m: float, yaw_ned_rad: float,
                       tilt_rad: tuple[float, float]) -> NDArray[np.float64] | None:
    """Image (x, y) -> ground offset (east, north) homography of the body-fixed camera (None: sees the horizon)."""
    return pixel_to_ground(camera.width_px, camera.height_px, camera.fov_deg, max(height_m, MIN_ALTITUDE_M),
                           tilt_rad[0], tilt_rad[1], yaw_ned_rad)


def _blank(camera: CameraModel) -> RenderedFrame:
    return RenderedFrame(
        image_bgr=np.zeros((camera.height_px, camera.width_px, 3), np.uint8),
        water_mask=np.zeros((camera.height_px, camera.width_px), bool),
    )


@dataclass(frozen=True)
class CameraPose:
    """How the camera hangs and moves beyond its position and yaw: the body's true (roll, pitch) [rad] (no gimbal),
    and, for motion blur and the imaging conditions' seeding, the vehicle's id and true ground velocity [m/s; east,
    north], with the mean wind [m/s; east, north] the cloud shadows drift with."""

    tilt_rad: tuple[float, float] = (0.0, 0.0)
    vehicle_id: int = 0
    velocity_en_mps: tuple[float, float] = (0.0, 0.0)
    wind_en_mps: tuple[float, float] = (0.0, 0.0)


LEVEL = CameraPose()


def render_frame(
    flood: FloodModel,
    t_s: float,
    position_enu_m: ArrayLike,
    yaw_ned_rad: float,
    camera: CameraModel = CameraModel(),
    seed: int = 0,
    pose: CameraPose = LEVEL,
    imaging: ImagingSpec = ImagingSpec(),
) -> RenderedFrame:
    """The image the downward camera of a drone at ``position_enu_m`` (east, north, up [m]) sees at flood time ``t_s``.

    ``yaw_ned_rad`` is the PX4 yaw (clockwise from north); ``pose`` the body's tilt (the camera is fixed to it) and
    what the imaging conditions need; ``imaging`` the conditions applied on top of the scene
    (:mod:`mock_autopilot.camera.imaging_conditions`; clean by default). A non-finite pose, or a tilt at which the
    camera sees the horizon, gives an all-black frame with an all-land mask (a failed camera, which perception
    reports as no measurement); a height below ``MIN_ALTITUDE_M`` is rendered from that height. Deterministic for
    given arguments.
    """
    pos = np.asarray(position_enu_m, dtype=float).reshape(-1)
    tilt = (float(pose.tilt_rad[0]), float(pose.tilt_rad[1]))
    if pos.size < 3 or not (np.all(np.isfinite(pos[:3])) and math.isfinite(yaw_ned_rad) and math.isfinite(t_s)
                            and math.isfinite(tilt[0]) and math.isfinite(tilt[1])):
        return _blank(camera)
    altitude_m = max(height_above_ground_m(flood, pos[:3]), MIN_ALTITUDE_M)
    gsd = camera.ground_sample_m(altitude_m)
    to_tile = _tile_map(camera, pos, altitude_m, gsd, yaw_ned_rad, tilt)
    if to_tile is None:
        return _blank(camera)
    m, h, w = MARGIN_PX, camera.height_px, camera.width_px
    at = (float(pos[0]), float(pos[1]), altitude_m)
    points = None
    if tilt == (0.0, 0.0) and _knows_depth(type(flood)):
        right, forward = _pixel_axes(w, h, m)
        grid = _level_points(camera, at, yaw_ned_rad, right[_CORNER_ROWS], forward[_CORNER_ROWS])
        depth = flood.depth_on_affine_grid_m(grid[:2, :2], t_s, shape_hw=(h + 2 * m, w + 2 * m))  # type: ignore
        water_padded = depth > flood.wet_depth_m  # type: ignore[attr-defined]
        image_corner = grid[2:, 2:]
    else:
        points = ground_points_en_m(camera, at, yaw_ned_rad, margin_px=m, tilt_rad=tilt)
        water_padded, depth = _water_under(flood, points, t_s, level=tilt == (0.0, 0.0))
        image_corner = points[m : m + 2, m : m + 2]
    water = water_padded[m : m + h, m : m + w]
    image = _ground_image(flood, t_s, pos, image_corner, water_padded, depth, to_tile, camera, gsd, seed)
    if not imaging.is_clean:
        if points is None:
            points = ground_points_en_m(camera, at, yaw_ned_rad, margin_px=m)
        image = apply_imaging(image, water, imaging, FrameInputs(
            seed=seed, vehicle_id=pose.vehicle_id, t_s=t_s, ground_points_en_m=points[m : m + h, m : m + w],
            height_m=altitude_m, ground_sample_m=gsd, position_en_m=(float(pos[0]), float(pos[1])),
            velocity_en_mps=pose.velocity_en_mps, wind_en_mps=pose.wind_en_mps))
    return RenderedFrame(image_bgr=image, water_mask=water.copy(), ground_sample_m=gsd)


def _tile_map(camera: CameraModel, pos: NDArray[np.float64], altitude_m: float, gsd: float, yaw_ned_rad: float,
              tilt: tuple[float, float]) -> NDArray[np.float64] | None:
    """Image pixel -> texture-tile pixel: 2x3 affine when level, 3x3 homography when tilted (None: the tilted camera
    sees the horizon)."""
    if tilt == (0.0, 0.0):
        return _texture_transform(camera, (float(pos[0]), float(pos[1])), gsd, yaw_ned_rad)
    to_ground = _tilted_homography(camera, altitude_m, yaw_ned_rad, tilt)
    if to_ground is None:
        return None
    return _tile_from_ground(float(pos[0]), float(pos[1])) @ to_ground @ _PIXEL_CENTRES


def _water_under(flood: FloodModel, points: NDArray[np.float64], t_s: float, level: bool
                 ) -> tuple[NDArray[np.bool_], NDArray[np.float32] | None]:
    """(water at each ground point, depth there or None for a flood without depth). A level footprint is an affine
    grid (one warp of the depth raster); a tilted one is not (per-point depth)."""
    if not _knows_depth(type(flood)):
        return np.asarray(flood.is_water(points, t_s), bool), None
    depth_of = flood.depth_on_affine_grid_m if level else flood.depth_m  # type: ignore[attr-defined]
    depth = depth_of(points, t_s)
    return depth > flood.wet_depth_m, depth  # type: ignore[attr-defined]


def _ground_image(flood: FloodModel, t_s: float, pos: NDArray[np.float64], image_corner: NDArray[np.float64],
                  water_padded: NDArray[np.bool_], depth: NDArray[np.float32] | None, to_tile: NDArray[np.float64],
                  camera: CameraModel, gsd: float, seed: int) -> NDArray[np.uint8]:
    """The scene through the lens: land and water textures, the wet shore band, depth shading and flow streaks, then
    optical blur, lighting (sun gradient, vignetting) and sensor noise. ``image_corner`` holds the ground points of
    the image's first two rows and columns of pixels (the streaks are laid along them)."""
    m, h, w = MARGIN_PX, camera.height_px, camera.width_px
    water = water_padded[m : m + h, m : m + w]
    textures = ground_textures(seed)
    any_water = bool(water_padded.any())
    if any_water:
        land, water_bgra = _sample_land_and_water(textures.land_and_water, to_tile, w, h)
    else:
        land = _sample_tile(textures.land_bgrw, to_tile, w, h)
    colour = cv2.cvtColor(land, cv2.COLOR_BGRA2BGR)
    wet_factor = None
    if any_water:
        if depth is None:
            wet_factor = _wet_shore_factor(water_padded, land, gsd)
        else:
            colour = cv2.multiply(colour, wet_shore_gain8(water_padded, m, land, gsd), scale=1.0 / GAIN_FIXED_ONE)
        water_colour = cv2.cvtColor(water_bgra, cv2.COLOR_BGRA2BGR)
        if depth is not None:
            flow = flood.flow_at_mps(pos[:2], t_s)  # type: ignore[attr-defined]
            water_colour = shade_by_depth(water_colour, np.ascontiguousarray(depth[m : m + h, m : m + w]),
                                          streaks(flow, image_corner, (h, w), seed))
        colour = cv2.copyTo(water_colour, water.view(np.uint8), colour)
    colour = cv2.GaussianBlur(colour, (3, 3), 0.6)
    effects = sensor_effects(seed, w, h)
    gain = effects.gain_bgr if wet_factor is None else cv2.multiply(effects.gain_bgr, wet_factor)
    shaded = cv2.multiply(colour, gain, dtype=cv2.CV_8U)
    noise = _noise_index(t_s, pos, seed)
    return cv2.subtract(cv2.add(shaded, effects.noise_up_bgr[noise]), effects.noise_down_bgr[noise])


def _wet_shore_factor(water_padded: NDArray[np.bool_], land_bgrw: NDArray[np.uint8], gsd: float
                      ) -> NDArray[np.float32]:
    """(H, W, 3) gain darkening the land within the seeded wet band of the water (wet soil is darker, and keeps
    more red than blue); 1 on the water and beyond the band."""
    m, h, w = MARGIN_PX, land_bgrw.shape[0], land_bgrw.shape[1]
    dry_padded = (~water_padded).view(np.uint8)
    distance_px = cv2.distanceTransform(dry_padded, cv2.DIST_L2, 3)[m : m + h, m : m + w]
    band = cv2.extractChannel(land_bgrw, 3)
    wetness = cv2.subtract(1.0, cv2.divide(distance_px, band, scale=gsd / WET_BAND_UNIT_M, dtype=cv2.CV_32F))
    wetness = cv2.multiply(wetness, dry_padded[m : m + h, m : m + w], dtype=cv2.CV_32F)  # 0 on the water
    cv2.max(wetness, 0.0, dst=wetness)
    return cv2.subtract(_ONE_BGR, cv2.multiply(cv2.merge([wetness, wetness, wetness]), _WET_DARKENING_SCALAR))


def _texture_transform(
    camera: CameraModel, anchor_en_m: tuple[float, float], gsd_m: float, yaw_ned_rad: float
) -> NDArray[np.float64]:
    """2x3 affine map from image pixel (column, row) to texture-tile pixel: the camera's ground projection is
    affine (nadir view of flat ground), so the textures are sampled with one ``warpAffine`` and no per-pixel maps.
    The tile repeats, so only the anchor's offset within its tile matters (keeps coordinates small)."""
    tile_m = TILE_PX * TILE_RESOLUTION_M
    east0, north0 = anchor_en_m
    origin_e = math.floor(east0 / tile_m) * tile_m
    origin_s = math.floor(-north0 / tile_m) * tile_m
    heading = yaw_ned_to_enu_rad(yaw_ned_rad)
    fwd_e, fwd_n = math.cos(heading), math.sin(heading)
    right_e, right_n = fwd_n, -fwd_e
    k = gsd_m / TILE_RESOLUTION_M
    c0 = 0.5 - camera.width_px / 2.0
    r0 = camera.height_px / 2.0 - 0.5
    return np.array(
        [
            [k * right_e, -k * fwd_e, (east0 - origin_e) / TILE_RESOLUTION_M + k * (c0 * right_e + r0 * fwd_e)],
            [-k * right_n, k * fwd_n, (-north0 - origin_s) / TILE_RESOLUTION_M - k * (c0 * right_n + r0 * fwd_n)],
        ]
    )


def _tile_from_ground(east0_m: float, north0_m: float) -> NDArray[np.float64]:
    """3x3 map from a ground offset (east, north) [m] from the point below the drone to texture-tile pixels (the
    tilted camera's textures are sampled through it and the camera's homography with one ``warpPerspective``)."""
    tile_m = TILE_PX * TILE_RESOLUTION_M
    origin_e = math.floor(east0_m / tile_m) * tile_m
    origin_s = math.floor(-north0_m / tile_m) * tile_m
    k = 1.0 / TILE_RESOLUTION_M
    return np.array([[k, 0.0, (east0_m - origin_e) * k], [0.0, -k, (-north0_m - origin_s) * k], [0.0, 0.0, 1.0]])


def _sample_tile(tile: NDArray[np.uint8], to_tile: NDArray[np.float64], width_px: int, height_px: int) -> NDArray[np.uint8]:
    """The tile seen through ``to_tile``: 2x3 affine (level camera) or 3x3 homography (tilted) from image pixel
    (x, y) to tile pixel."""
    warp = cv2.warpAffine if to_tile.shape[0] == 2 else cv2.warpPerspective
    return warp(tile, to_tile, (width_px, height_px), flags=cv2.INTER_NEAREST | cv2.WARP_INVERSE_MAP,
                borderMode=cv2.BORDER_WRAP)


def _sample_land_and_water(texels: NDArray[np.uint16], to_tile: NDArray[np.float64], width_px: int,
                           height_px: int) -> tuple[NDArray[np.uint8], NDArray[np.uint8]]:
    """(land B, G, R, band; water B, G, R, 0) images, both (H, W, 4) uint8, seen through ``to_tile``: one
    nearest-neighbour warp of the interleaved tiles (``appearance.GroundTextures.land_and_water``; the same texels
    as two warps would pick), then the 8-byte texels split into their two 4-byte halves."""
    both = _sample_tile(texels, to_tile, width_px, height_px)  # type: ignore[arg-type]
    land, water = cv2.split(both.view(np.int32))
    return land.view(np.uint8).reshape(height_px, width_px, 4), water.view(np.uint8).reshape(height_px, width_px, 4)


def _noise_index(t_s: float, position_enu_m: NDArray[np.float64], seed: int) -> int:
    """Which cached noise frame this frame uses: varies frame to frame, deterministic in the arguments."""
    key = int(round(t_s * 50.0)) * 7919 + int(round(position_enu_m[0] * 10.0)) * 104729
    key += int(round(position_enu_m[1] * 10.0)) * 1299709 + seed * 15485863
    return key % NOISE_FRAMES
