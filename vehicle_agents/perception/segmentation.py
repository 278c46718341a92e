"""What eq 5 and Algorithm 1 need from one downward camera frame (paper §III-A.1).

The perception is never told the truth. ``water_mask.segment_water`` classifies the pixels (no fixed colour of
water: see that module); a class under ``MIN_CLASS_FRACTION`` of the image is absent, and a frame of one class sets
Algorithm 1's climb flags. The water and land centroids, their midpoint (eq 5's ``p − q``) and sub-pixel edge points
are projected to the ground through the body-fixed camera's pinhole geometry at the height above ground and the
attitude the autopilot reports (:mod:`comms.camera_projection`; level, SPEC §3's ``2 h tan(fov/2) / W`` metres per
pixel rotated by the yaw), as offsets from the point below the drone along east/north.

Bad input (not an image, wrong size, black, saturated, featureless, NaN altitude, bad field of view) gives
``PerceptionResult.no_measurement()``; nothing raises.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

from comms.camera_projection import pixel_to_ground, project_pixels
from vehicle_agents.perception.boundary_steps import boundary_steps, step_points_px
from vehicle_agents.perception.grey_water import ShoreByColour
from vehicle_agents.perception.main_boundary import main_boundary_kept
from vehicle_agents.perception.result import PerceptionResult
from vehicle_agents.perception.shore import shore_along_steps
from vehicle_agents.perception.water_mask import segment_water_with_shore

MIN_SIDE_PX = 8
"""Smallest image side accepted [px]."""
MAX_SIDE_PX = 4096
"""Largest image side accepted [px]."""
MIN_CLASS_FRACTION = 0.005
"""A class covering less of the image than this is treated as absent (noise, a few stray pixels)."""
DARK_MEAN_DN = 12.0
"""A frame darker than this on average is a black (failed or covered) camera."""
SATURATED_FRACTION = 0.9
"""A frame with this share of pixels at 255 in every channel is blown out."""
FLAT_STD_DN = 1.0
"""A frame whose grey level varies less than this holds no scene (a test pattern or a frozen sensor)."""
MAX_EDGE_POINTS = 64
"""At most this many edge points are returned (evenly taken along the edge)."""



def perceive(
    image_bgr: Any,
    altitude_m: float,
    fov_deg: float,
    yaw_ned_rad: float = 0.0,
    *,
    roll_rad: float = 0.0,
    pitch_rad: float = 0.0,
    max_edge_points: int = MAX_EDGE_POINTS,
) -> PerceptionResult:
    """Segment one downward frame and measure, relative to the drone, what eq 5 and Algorithm 1 use.

    ``image_bgr``: (H, W, 3) uint8 BGR, image up = vehicle forward. ``altitude_m``: height above the ground [m].
    ``fov_deg``: horizontal field of view across the image width. ``yaw_ned_rad``: PX4 yaw (clockwise from north),
    used to rotate image axes into east/north. ``roll_rad``, ``pitch_rad``: the body's attitude as the autopilot
    reports it (ATTITUDE); the camera is fixed to the body, so pixels are projected to the ground through it
    (:mod:`comms.camera_projection`). Never raises: unusable input gives ``no_measurement()``.
    """
    try:
        return _perceive(image_bgr, altitude_m, fov_deg, (float(roll_rad), float(pitch_rad), float(yaw_ned_rad)),
                         max_edge_points)
    except (ValueError, TypeError, cv2.error, FloatingPointError, OverflowError):
        return PerceptionResult.no_measurement()


def _usable_image(image: Any) -> NDArray[np.uint8] | None:
    """The frame as contiguous (H, W, 3) uint8 BGR (an alpha channel is dropped), or None if it is not one."""
    if not isinstance(image, np.ndarray) or image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] not in (3, 4):
        return None
    h, w = image.shape[:2]
    if not (MIN_SIDE_PX <= h <= MAX_SIDE_PX and MIN_SIDE_PX <= w <= MAX_SIDE_PX):
        return None
    return np.ascontiguousarray(image[..., :3])


def _unusable_exposure(image: NDArray[np.uint8]) -> bool:
    grey = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    mean, std = cv2.meanStdDev(grey)
    if float(mean[0, 0]) < DARK_MEAN_DN or float(std[0, 0]) < FLAT_STD_DN:
        return True
    if float(mean[0, 0]) < SATURATED_FRACTION * 254.0:
        return False  # a blown-out frame's mean is at least that
    _, saturated = cv2.threshold(grey, 253, 1, cv2.THRESH_BINARY)  # grey 254-255: every channel at or near 255
    return cv2.countNonZero(saturated) >= SATURATED_FRACTION * grey.size


def _perceive(
    image: Any, altitude_m: float, fov_deg: float, attitude_rad: tuple[float, float, float], max_edge_points: int
) -> PerceptionResult:
    altitude_m, fov_deg = float(altitude_m), float(fov_deg)
    if not (math.isfinite(altitude_m) and altitude_m > 0.0 and math.isfinite(fov_deg) and 0.0 < fov_deg < 170.0):
        return PerceptionResult.no_measurement()
    image = _usable_image(image) if all(math.isfinite(a) for a in attitude_rad) else None
    if image is None:
        return PerceptionResult.no_measurement()
    h, w = image.shape[:2]
    footprint_m = 2.0 * altitude_m * math.tan(math.radians(fov_deg) / 2.0)
    to_ground = pixel_to_ground(w, h, fov_deg, altitude_m, *attitude_rad)
    if to_ground is None or _unusable_exposure(image):
        return PerceptionResult.no_measurement(footprint_m)
    mask, score, threshold, shore = segment_water_with_shore(image, ground_sample_m=footprint_m / w)
    water_fraction = cv2.countNonZero(mask.view(np.uint8)) / mask.size if mask is not None else float(
        cv2.mean(score)[0] > threshold)
    if not MIN_CLASS_FRACTION <= water_fraction <= 1.0 - MIN_CLASS_FRACTION:
        only_water = water_fraction > 0.5
        return PerceptionResult(has_edge=False, water_fraction=float(water_fraction), only_land=not only_water,
                                only_water=only_water, footprint_side_m=footprint_m, ground_sample_m=footprint_m / w)
    assert mask is not None  # a one-class frame has a fraction of 0 or 1
    return _edge_result(mask, score, threshold, to_ground, footprint_m, max_edge_points, shore)


def _edge_result(mask: NDArray[np.bool_], score: NDArray[np.uint8], threshold: float,
                 to_ground: NDArray[np.float64], footprint_m: float, max_edge_points: int,
                 shore: ShoreByColour | None = None) -> PerceptionResult:
    """What a frame holding both classes tells: centroids and their midpoint (eq 5's ``p − q``), the edge points,
    its normal (water to land) and tangent (water on the left), all on the ground; and the shore points placed by
    colour when the grey-water cue split the frame, in the order of the edge points (each on the same boundary step
    as its edge point)."""
    h, w = mask.shape
    n = h * w
    n_water, sum_x, sum_y = _water_moments(mask)
    # Pixel-centre moments (x = column + 0.5, y = row + 0.5); the whole image's are known in closed form.
    water_x, water_y = sum_x / n_water + 0.5, sum_y / n_water + 0.5
    water_px = np.array([water_x, water_y])
    land_px = np.array([(n * w / 2.0 - water_x * n_water) / (n - n_water),
                        (n * h / 2.0 - water_y * n_water) / (n - n_water)])
    water_en, land_en = _ground_centroids(to_ground, mask, water_px, land_px, n_water)
    edge_en, shore_en = _shore_on_ground(mask, score, threshold, to_ground, shore)
    (water_e, water_n), (land_e, land_n) = water_en.tolist(), land_en.tolist()
    normal = _edge_normal(edge_en, land_e - water_e, land_n - water_n)
    if normal is None:
        return PerceptionResult.no_measurement(footprint_m)
    tangent = np.array([-normal[1], normal[0]])
    along = _along_the_edge(edge_en, tangent, max_edge_points)
    return PerceptionResult(
        has_edge=True,
        water_fraction=float(n_water / n),
        only_land=False,
        only_water=False,
        footprint_side_m=footprint_m,
        midpoint_offset_en_m=np.array([0.5 * (water_e + land_e), 0.5 * (water_n + land_n)]),
        water_centroid_en_m=water_en,
        land_centroid_en_m=land_en,
        edge_normal_en=normal,
        edge_tangent_en=tangent,
        edge_points_en_m=edge_en[along],
        shore_points_en_m=None if shore_en is None else shore_en[along],
        water_centroid_px=water_px,
        land_centroid_px=land_px,
        ground_sample_m=footprint_m / w,
        water_mask=mask,
    )


def _shore_on_ground(mask: NDArray[np.bool_], score: NDArray[np.generic], threshold: float,
                     to_ground: NDArray[np.float64], shore: ShoreByColour | None
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """The sub-pixel points of ``mask``'s boundary on its shore (:mod:`vehicle_agents.perception.boundary_steps`,
    :mod:`vehicle_agents.perception.main_boundary`), and the shore placed by colour along the same steps when the
    grey-water split gave its colour score (None otherwise, or when colour cannot place it), projected to the
    ground: (K, 2) offsets from the drone [m; east, north]."""
    m8 = mask.view(np.uint8)
    steps = boundary_steps(m8)
    if steps is None:
        return np.zeros((0, 2)), None
    points_px = step_points_px(steps, score, threshold)
    kept = main_boundary_kept(points_px, mask.shape)
    if kept is not None:
        steps, points_px = steps.subset(kept), points_px[kept]
    shore_px = None if shore is None else shore_along_steps(steps, m8, shore.score)
    if shore_px is None:
        return project_pixels(to_ground, points_px[:, 0], points_px[:, 1]), None
    both_px = np.concatenate((points_px, shore_px))
    both_en = project_pixels(to_ground, both_px[:, 0], both_px[:, 1])
    return both_en[: len(points_px)], both_en[len(points_px):]


def _water_moments(mask: NDArray[np.bool_]) -> tuple[float, float, float]:
    """(pixel count, sum of columns, sum of rows) of the water pixels: the image moments m00, m10 and m01, from the
    per-column and per-row counts in integers (exact, as ``cv2.moments`` gives them, at less cost; OpenCV reduces
    a row to 32-bit integers several times faster than to floats)."""
    m8 = mask.view(np.uint8)
    columns = cv2.reduce(m8, 0, cv2.REDUCE_SUM, dtype=cv2.CV_32S).ravel()
    rows = cv2.reduce(m8, 1, cv2.REDUCE_SUM, dtype=cv2.CV_32S).ravel()
    return float(columns.sum()), float(columns @ _indices(columns.size)), float(rows @ _indices(rows.size))


@lru_cache(maxsize=8)
def _indices(n: int) -> NDArray[np.int64]:
    return np.arange(n, dtype=np.int64)


def _edge_normal(edge_en: NDArray[np.float64], to_land_e: float, to_land_n: float) -> NDArray[np.float64] | None:
    """Unit normal of the edge, from water to land: across the principal axis of the edge points (closed form for
    2x2), turned towards the land centroid (``to_land_e``, ``to_land_n``: water to land centroid [m]); the
    centroid line itself when there are too few points. The two-element vectors are plain floats (an array
    operation costs more than the arithmetic)."""
    normal_e, normal_n = to_land_e, to_land_n
    if edge_en.shape[0] >= 2:
        d = edge_en - np.add.reduce(edge_en, axis=0) / edge_en.shape[0]  # the mean, without np.mean's wrapper
        sxx, syy, sxy = float(d[:, 0] @ d[:, 0]), float(d[:, 1] @ d[:, 1]), float(d[:, 0] @ d[:, 1])
        axis = 0.5 * math.atan2(2.0 * sxy, sxx - syy)
        pca_e, pca_n = -math.sin(axis), math.cos(axis)
        if pca_e * normal_e + pca_n * normal_n >= 0.0:
            normal_e, normal_n = pca_e, pca_n
        else:
            normal_e, normal_n = -pca_e, -pca_n
    length = math.hypot(normal_e, normal_n)
    if length <= 0.0 or not math.isfinite(length):
        return None
    return np.array([normal_e / length, normal_n / length])


def _along_the_edge(edge_en: NDArray[np.float64], tangent: NDArray[np.float64], max_points: int
                    ) -> NDArray[np.intp]:
    """Indices of the edge points sorted along the tangent, at most ``max_points`` of them taken evenly."""
    order = (edge_en @ tangent).argsort(kind="stable")
    k = order.shape[0]
    if k > max_points > 1:
        order = order[np.arange(max_points) * (k - 1) // (max_points - 1)]
    return order


def _ground_centroids(to_ground: NDArray[np.float64], mask: NDArray[np.bool_], water_px: NDArray[np.float64],
                      land_px: NDArray[np.float64], n_water: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Mean ground offset [m; east, north] of the water and of the land pixels. Level, the projection is affine and
    maps the pixel centroids exactly. Tilted, every pixel centre p = (x, y, 1) lands at (g0·p, g1·p) / g2·p, so a
    class's sum of ground points is g0 and g1 applied to its sums of p / g2·p: three moments of one weight image,
    taken from its per-column and per-row sums over the class."""
    if to_ground[2, 0] == 0.0 and to_ground[2, 1] == 0.0:
        return _project_point(to_ground, water_px), _project_point(to_ground, land_px)
    height, width = mask.shape
    x, y = _pixel_centre_coordinates(width), _pixel_centre_coordinates(height)
    weight = 1.0 / ((to_ground[2, 1] * y + to_ground[2, 2])[:, None] + to_ground[2, 0] * x)
    water_weight = weight * mask
    all_columns, water_columns = weight.sum(axis=0), water_weight.sum(axis=0)
    all_moments = np.array([all_columns @ x, weight.sum(axis=1) @ y, all_columns.sum()])
    water_moments = np.array([water_columns @ x, water_weight.sum(axis=1) @ y, water_columns.sum()])
    water_sum = to_ground[:2] @ water_moments
    land_sum = to_ground[:2] @ (all_moments - water_moments)
    return water_sum / n_water, land_sum / (height * width - n_water)


def _project_point(homography: NDArray[np.float64], xy: NDArray[np.float64]) -> NDArray[np.float64]:
    """``comms.camera_projection.project_pixels`` of one point, in the same arithmetic on plain floats."""
    (g00, g01, g02), (g10, g11, g12), (g20, g21, g22) = homography.tolist()
    x, y = float(xy[0]), float(xy[1])
    w = g20 * x + g21 * y + g22
    return np.array([(g00 * x + g01 * y + g02) / w, (g10 * x + g11 * y + g12) / w])


@lru_cache(maxsize=8)
def _pixel_centre_coordinates(n: int) -> NDArray[np.float64]:
    """(n,) pixel-centre coordinates 0.5 .. n − 0.5 along one image axis."""
    return np.arange(n) + 0.5
