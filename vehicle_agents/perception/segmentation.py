"""Land/water segmentation of the downward camera image and the measurement of eq 5 (paper §III-A.1, Alg. 1).

The segmentation is told nothing about the scene: water is told from land by colour alone. In CIE L*a*b* the b*
axis runs blue -> yellow; water (blue-grey, reflecting the sky) sits below neutral, vegetation and soil, wet or
dry, above it. We smooth b*, split it with Otsu's threshold, and keep Otsu's split only when it looks like
water against land (the darker class is bluish, the lighter is not, and they are well apart); otherwise the
image holds one class and a fixed colour threshold says which. Morphological opening and closing remove specks.

From the mask: the water fraction, the land and water centroids, their midpoint ``p`` relative to the drone
(eq 5's ``p − q``, in metres east/north after rotating by the yaw), the edge normal and tangent, and the edge
pixels as metric offsets. Nothing here raises on bad input: unusable frames give ``no_measurement()``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

from comms.frames import yaw_ned_to_enu_rad
from vehicle_agents.perception.result import PerceptionResult


@dataclass(frozen=True)
class SegmentationParams:
    """Tuning of the colour segmentation (b* values are OpenCV 8-bit Lab: 128 is neutral)."""

    neutral_b: float = 131.0
    """Fixed b* threshold used when the image holds only one class: below it is water."""
    water_max_b: float = 128.0
    """Otsu's darker class must have a mean b* below this to be water (bluish)."""
    land_min_b: float = 134.0
    """Otsu's lighter class must have a mean b* above this to be land (yellowish/greenish)."""
    min_class_gap_b: float = 12.0
    """Otsu's two classes must differ by at least this much in mean b*."""
    blur_px: int = 5
    """Side of the Gaussian smoothing kernel applied to b* before thresholding."""
    morphology_px: int = 3
    """Side of the elliptical opening/closing kernel."""
    min_region_fraction: float = 0.005
    """A class covering less than this fraction of the image counts as absent (Algorithm 1's test)."""
    max_edge_points: int = 64
    """At most this many edge points are reported (evenly spread along the edge)."""
    dark_level: float = 12.0
    """Mean grey level below which the frame is too dark to use."""
    saturated_fraction: float = 0.5
    """Frames with more than this fraction of saturated pixels are unusable."""


DEFAULT_PARAMS = SegmentationParams()


def _usable_image(image_bgr: object) -> NDArray[np.uint8] | None:
    """The image as contiguous (H, W, 3) uint8 BGR, or None if it is not a usable colour frame."""
    if not isinstance(image_bgr, np.ndarray) or image_bgr.dtype != np.uint8 or image_bgr.ndim != 3:
        return None
    if image_bgr.shape[2] == 4:
        image_bgr = image_bgr[..., :3]
    if image_bgr.shape[2] != 3 or image_bgr.shape[0] < 8 or image_bgr.shape[1] < 8:
        return None
    return np.ascontiguousarray(image_bgr)


def segment_water(image_bgr: object, params: SegmentationParams = DEFAULT_PARAMS) -> NDArray[np.bool_] | None:
    """(H, W) water mask of a BGR camera frame, or None when the frame is unusable (not a colour image,
    too small, black or saturated)."""
    image = _usable_image(image_bgr)
    if image is None:
        return None
    grey = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    if float(grey.mean()) < params.dark_level:
        return None
    if np.count_nonzero(grey >= 250) > params.saturated_fraction * grey.size:
        return None
    b_star = cv2.cvtColor(image, cv2.COLOR_BGR2Lab)[..., 2]
    k = params.blur_px | 1
    b_star = cv2.GaussianBlur(b_star, (k, k), 0)
    threshold, upper = cv2.threshold(b_star, 0, 255, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
    upper_mask = upper.view(bool)
    n_upper = int(np.count_nonzero(upper_mask))
    n_total = upper_mask.size
    otsu_ok = 0 < n_upper < n_total
    if otsu_ok:
        total = float(b_star.sum(dtype=np.float64))
        upper_sum = float(b_star[upper_mask].sum(dtype=np.float64))
        mean_upper = upper_sum / n_upper
        mean_lower = (total - upper_sum) / (n_total - n_upper)
        otsu_ok = (
            mean_lower < params.water_max_b
            and mean_upper > params.land_min_b
            and mean_upper - mean_lower >= params.min_class_gap_b
        )
    if otsu_ok:
        water = cv2.bitwise_not(upper)
    else:
        _, water = cv2.threshold(b_star, params.neutral_b, 255, cv2.THRESH_BINARY_INV)
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (params.morphology_px, params.morphology_px))
    water = cv2.morphologyEx(water, cv2.MORPH_OPEN, kernel)
    water = cv2.morphologyEx(water, cv2.MORPH_CLOSE, kernel)
    return water.view(bool)


def _edge_pixels(water_u8: NDArray[np.uint8], max_points: int) -> NDArray[np.float64]:
    """Shoreline pixels in order along the edge [px; column, row of pixel centres], without the image border."""
    h, w = water_u8.shape
    contours, _ = cv2.findContours(water_u8, cv2.RETR_LIST, cv2.CHAIN_APPROX_NONE)
    chains = []
    for contour in contours:
        pts = contour.reshape(-1, 2)
        inside = (pts[:, 0] > 0) & (pts[:, 0] < w - 1) & (pts[:, 1] > 0) & (pts[:, 1] < h - 1)
        if np.count_nonzero(inside) >= 3:
            chains.append(pts[inside])
    if not chains:
        return np.zeros((0, 2))
    pts = np.concatenate(chains).astype(np.float64) + 0.5
    if len(pts) > max_points:
        pts = pts[np.linspace(0, len(pts) - 1, max_points).round().astype(int)]
    return pts


def perceive(
    image_bgr: object,
    altitude_m: float,
    fov_deg: float,
    yaw_ned_rad: float = 0.0,
    params: SegmentationParams = DEFAULT_PARAMS,
) -> PerceptionResult:
    """Measure the flood edge in one downward camera frame (eq 5, Algorithm 1).

    ``altitude_m`` is the height above the ground, ``fov_deg`` the horizontal field of view (across the image
    width), ``yaw_ned_rad`` the PX4 yaw used to turn image axes into east/north. Never raises: unusable images,
    non-finite or non-positive altitude, a field of view outside (0, 180) or a non-finite yaw give
    ``PerceptionResult.no_measurement()``.
    """
    try:
        return _perceive(image_bgr, float(altitude_m), float(fov_deg), float(yaw_ned_rad), params)
    except (TypeError, ValueError, cv2.error):
        return PerceptionResult.no_measurement()


def _perceive(
    image_bgr: object, altitude_m: float, fov_deg: float, yaw_ned_rad: float, params: SegmentationParams
) -> PerceptionResult:
    if not (math.isfinite(altitude_m) and altitude_m > 0.0 and math.isfinite(yaw_ned_rad)):
        return PerceptionResult.no_measurement()
    if not (math.isfinite(fov_deg) and 0.0 < fov_deg < 180.0):
        return PerceptionResult.no_measurement()
    water = segment_water(image_bgr, params)
    if water is None:
        return PerceptionResult.no_measurement()
    h, w = water.shape
    footprint_m = 2.0 * altitude_m * math.tan(math.radians(fov_deg) / 2.0)
    gsd = footprint_m / w

    water_u8 = water.view(np.uint8)
    n_water = int(np.count_nonzero(water_u8))
    fraction = n_water / water.size
    only_water = fraction >= 1.0 - params.min_region_fraction
    only_land = fraction <= params.min_region_fraction
    if only_water or only_land:
        return PerceptionResult(
            has_edge=False,
            water_fraction=fraction,
            only_land=only_land,
            only_water=only_water,
            footprint_side_m=footprint_m,
            ground_sample_m=gsd,
        )

    # Image axes -> world: image right = vehicle right, image up = vehicle forward.
    heading = yaw_ned_to_enu_rad(yaw_ned_rad)
    forward_en = np.array([math.cos(heading), math.sin(heading)])
    right_en = np.array([forward_en[1], -forward_en[0]])

    def to_en_m(px: NDArray[np.float64]) -> NDArray[np.float64]:
        right_m = (px[..., 0] - w / 2.0) * gsd
        forward_m = (h / 2.0 - px[..., 1]) * gsd
        return right_m[..., None] * right_en + forward_m[..., None] * forward_en

    m_all = cv2.moments(np.ones_like(water_u8), binaryImage=True)
    m_water = cv2.moments(water_u8, binaryImage=True)
    n_land = water.size - n_water
    water_px = np.array([m_water["m10"] / n_water, m_water["m01"] / n_water]) + 0.5
    land_px = np.array([(m_all["m10"] - m_water["m10"]) / n_land, (m_all["m01"] - m_water["m01"]) / n_land]) + 0.5
    water_en = to_en_m(water_px)
    land_en = to_en_m(land_px)

    normal = land_en - water_en
    normal /= max(float(np.linalg.norm(normal)), 1e-12)
    edge_px = _edge_pixels(water_u8, params.max_edge_points)
    edge_en = to_en_m(edge_px) if len(edge_px) else np.zeros((0, 2))
    if len(edge_en) >= 6:
        centred = edge_en - edge_en.mean(axis=0)
        _, singular, vt = np.linalg.svd(centred, full_matrices=False)
        if singular[0] > 2.0 * singular[1]:
            pca_normal = np.array([-vt[0, 1], vt[0, 0]])
            normal = pca_normal if pca_normal @ normal >= 0.0 else -pca_normal
    # Contour pixels are the water-side row of the edge; the shoreline lies half a pixel towards land.
    if len(edge_en):
        edge_en = edge_en + 0.5 * gsd * normal
    tangent = np.array([-normal[1], normal[0]])
    return PerceptionResult(
        has_edge=True,
        water_fraction=fraction,
        only_land=False,
        only_water=False,
        footprint_side_m=footprint_m,
        midpoint_offset_en_m=0.5 * (water_en + land_en),
        water_centroid_en_m=water_en,
        land_centroid_en_m=land_en,
        edge_normal_en=normal,
        edge_tangent_en=tangent,
        edge_points_en_m=edge_en,
        water_centroid_px=(float(water_px[0]), float(water_px[1])),
        land_centroid_px=(float(land_px[0]), float(land_px[1])),
        ground_sample_m=gsd,
    )
