"""Hard imagery on top of the rendered scene: what a real small camera on a real day does to the picture.

Scene effects first (they are in the world): turbid brown water beside brown soil (per mission seed, with the
``turbid_water_probability``), cloud shadows drifting with the mean wind, the sun's glint on the water, floating
debris. Then the camera's own: motion blur along the ground's motion in the image, vignetting, exposure and
white-balance drift (auto-exposure and auto-white-balance hunting slowly), sensor noise, JPEG compression.

Everything random is drawn from the mission seed: world-anchored fields (shadows, debris) and the sun from the seed
alone, the drifts from (seed, vehicle), the noise from (seed, vehicle, frame time), so one seed renders the same
frame twice and two seeds differ. Pure numpy/OpenCV, cached per seed; the renderer calls :func:`apply_imaging`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import cv2
import numpy as np
from numpy.typing import NDArray

from mission_plan.imaging import ImagingSpec
from mock_autopilot.camera.hard_scene import cloud_shadow_gain, debris_layer, glint_layer, turbid_recolour

NOISE_BANK_FRAMES = 16
"""Unit-Gaussian noise frames kept per (seed, size); each frame takes one at a seeded random offset."""
DRIFT_PERIODS_S = (37.0, 11.0)
"""Periods of the two sinusoids whose seeded mix is the slow exposure / white-balance drift [s]."""


@dataclass(frozen=True)
class FrameInputs:
    """What the imaging conditions need to know about one frame besides the image and the truth mask."""

    seed: int
    """Mission seed."""
    vehicle_id: int
    t_s: float
    """Flood time of the frame [s] (shadows drift on it; noise and drifts follow it)."""
    ground_points_en_m: NDArray[np.float64]
    """(H, W, 2) ground point [m; east, north] under each pixel centre."""
    height_m: float
    """Camera height above the ground [m]."""
    ground_sample_m: float
    """Ground size of one pixel [m/px]."""
    position_en_m: tuple[float, float]
    """The point below the drone [m; east, north] (where the glint sits relative to it)."""
    velocity_en_mps: tuple[float, float] = (0.0, 0.0)
    """The drone's true ground velocity [m/s; east, north] (the ground moves the other way in the image)."""
    wind_en_mps: tuple[float, float] = (0.0, 0.0)
    """Mean wind the cloud shadows drift with [m/s; east, north]."""


def water_is_turbid(spec: ImagingSpec, seed: int) -> bool:
    """Whether this mission seed's water is turbid brown (a share ``turbid_water_probability`` of seeds)."""
    if spec.turbid_water_probability <= 0.0:
        return False
    return bool(np.random.default_rng([int(seed) & 0xFFFFFFFF, 0x7B1D]).random() < spec.turbid_water_probability)


def apply_imaging(image_bgr: NDArray[np.uint8], water_mask: NDArray[np.bool_], spec: ImagingSpec,
                  frame: FrameInputs) -> NDArray[np.uint8]:
    """The frame as the camera delivers it under ``spec`` (the image itself when ``spec`` is clean)."""
    if spec.is_clean:
        return image_bgr
    image = image_bgr.astype(np.float32)
    if water_is_turbid(spec, frame.seed):
        image = turbid_recolour(image, water_mask, frame.seed)
    if spec.floating_debris and water_mask.any():
        colour, alpha = debris_layer(frame.ground_points_en_m, frame.seed)
        cover = cv2.bitwise_and(cv2.compare(alpha, 0.5, cv2.CMP_GT), water_mask.view(np.uint8) * np.uint8(255))
        image = cv2.copyTo(colour, cover, image)
    if spec.cloud_shadow_cover > 0.0:
        image *= cloud_shadow_gain(frame.ground_points_en_m, frame.t_s, frame.wind_en_mps, spec.cloud_shadow_cover,
                                   frame.seed)
    if spec.sun_glint and water_mask.any():
        glint = glint_layer(frame.ground_points_en_m, frame.position_en_m, frame.height_m, frame.t_s, frame.seed,
                            frame.vehicle_id)
        image = cv2.add(image, cv2.merge([glint, glint, glint]), mask=water_mask.view(np.uint8), dst=image.copy())
    if spec.exposure_time_s > 0.0:
        image = _motion_blur(image, frame, spec.exposure_time_s)
    gain = np.ones(3, np.float32)
    if spec.exposure_drift > 0.0:
        gain *= 1.0 + spec.exposure_drift * _drift(frame, 0)
    if spec.white_balance_drift > 0.0:
        gain *= 1.0 + spec.white_balance_drift * np.array([_drift(frame, c + 1) for c in range(3)], np.float32)
    image *= gain
    if spec.vignetting > 0.0:
        image *= _vignette(image.shape[1], image.shape[0], spec.vignetting)[..., None]
    if spec.noise_sigma > 0.0:
        image += np.float32(spec.noise_sigma) * _noise(frame, image.shape)
    out = cv2.convertScaleAbs(cv2.max(image, 0.0))
    if spec.jpeg_quality > 0:
        ok, encoded = cv2.imencode(".jpg", out, [cv2.IMWRITE_JPEG_QUALITY, int(spec.jpeg_quality)])
        if ok:
            out = cv2.imdecode(encoded, cv2.IMREAD_COLOR)
    return out


def _frame_rng(frame: FrameInputs, tag: int) -> np.random.Generator:
    """A generator for one vehicle's frame: the same (seed, vehicle, time) always draws the same numbers."""
    t_ms = int(round(frame.t_s * 1000.0))
    return np.random.default_rng([int(frame.seed) & 0xFFFFFFFF, int(frame.vehicle_id) & 0xFFFFFFFF,
                                  t_ms & 0xFFFFFFFF, tag])


@lru_cache(maxsize=256)
def _drift_shape(seed: int, vehicle_id: int, channel: int) -> tuple[float, float, float]:
    """(phase of the slow sinusoid, phase of the fast one, weight of the slow one) for one drift."""
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, int(vehicle_id) & 0xFFFFFFFF, channel, 0xD41F])
    phase = rng.uniform(0.0, 2.0 * math.pi, 2)
    return float(phase[0]), float(phase[1]), float(rng.uniform(0.3, 0.7))


def _drift(frame: FrameInputs, channel: int) -> float:
    """A slow seeded drift in [-1, 1] per (seed, vehicle, channel): two sinusoids of random phase and weight."""
    *phase, weight = _drift_shape(frame.seed, frame.vehicle_id, channel)
    slow, fast = (math.sin(2.0 * math.pi * frame.t_s / period + p) for period, p in zip(DRIFT_PERIODS_S, phase))
    return float(weight * slow + (1.0 - weight) * fast)


@lru_cache(maxsize=8)
def _vignette(width_px: int, height_px: int, corner_loss: float) -> NDArray[np.float32]:
    """Radial gain ``1 − v (r / r_corner)²``: 1 at the centre, ``1 − vignetting`` in the corners."""
    y, x = np.mgrid[0:height_px, 0:width_px].astype(np.float32)
    x = (x + 0.5) / width_px - 0.5
    y = (y + 0.5) / height_px - 0.5
    r2 = (x * x + y * y) / 0.5
    return (1.0 - corner_loss * r2).astype(np.float32)


@lru_cache(maxsize=8)
def _noise_bank(seed: int, height_px: int, width_px: int) -> NDArray[np.float32]:
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, height_px, width_px, 0x9015])
    return rng.standard_normal((NOISE_BANK_FRAMES, height_px * width_px * 3)).astype(np.float32)


def _noise(frame: FrameInputs, shape: tuple[int, ...]) -> NDArray[np.float32]:
    """Unit Gaussian noise for this frame: a bank frame rolled by a per-frame offset (cheap, and never the same
    pattern twice in a row)."""
    h, w = shape[:2]
    bank = _noise_bank(frame.seed, h, w)
    rng = _frame_rng(frame, 0x0153)
    row = bank[int(rng.integers(NOISE_BANK_FRAMES))]
    return np.roll(row, int(rng.integers(row.size))).reshape(h, w, 3)


def _motion_blur(image: NDArray[np.float32], frame: FrameInputs, exposure_time_s: float) -> NDArray[np.float32]:
    """Blur along the ground's motion in the image: the drone's ground velocity over the exposure, in pixels."""
    gsd = max(frame.ground_sample_m, 1e-6)
    points = frame.ground_points_en_m
    right = points[0, -1] - points[0, 0]
    up = points[0, 0] - points[-1, 0]
    right = right / max(float(np.hypot(*right)), 1e-12)
    up = up / max(float(np.hypot(*up)), 1e-12)
    v = np.asarray(frame.velocity_en_mps, float)
    length_px = exposure_time_s * float(np.hypot(*v)) / gsd
    if length_px < 1e-3:
        return image
    # Image (x right, y down) direction of the drone's motion; the blur streak is symmetric, so its sign is moot.
    dx, dy = float(v @ right), -float(v @ up)
    norm = math.hypot(dx, dy)
    return cv2.filter2D(image, -1, _line_kernel(length_px, dx / norm, dy / norm), borderType=cv2.BORDER_REFLECT)


def _line_kernel(length_px: float, dx: float, dy: float) -> NDArray[np.float32]:
    """A normalised kernel averaging along a segment of ``length_px`` (sub-pixel lengths splat bilinearly)."""
    half = int(math.ceil(length_px / 2.0)) + 1
    size = 2 * half + 1
    kernel = np.zeros((size, size), np.float32)
    samples = max(8, int(math.ceil(length_px * 8)))
    for s in np.linspace(-0.5, 0.5, samples) * length_px:
        x, y = half + s * dx, half + s * dy
        x0, y0 = int(math.floor(x)), int(math.floor(y))
        fx, fy = x - x0, y - y0
        kernel[y0, x0] += (1 - fx) * (1 - fy)
        kernel[y0, x0 + 1] += fx * (1 - fy)
        kernel[y0 + 1, x0] += (1 - fx) * fy
        kernel[y0 + 1, x0 + 1] += fx * fy
    return kernel / kernel.sum()
