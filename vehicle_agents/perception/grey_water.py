"""Water that is not blue (silt-laden, under a grey sky or a cloud shadow), told from the land beside it by four
physical cues, each computed per pixel on the frame after a 3x3 median (which removes sensor noise, JPEG ringing
and the glint's single-pixel sparkle):

- **chromaticity** ``B / (B + G + R)``: the water's surface mirrors the sky, which adds a grey-blue component to
  whatever colour the water carries, so it lies above the soil it borders;
- **saturation** ``(max − min) / (B + G + R)``: for the same reason the water is less saturated;
- **brightness** (log grey): the mirrored sky makes the water lighter than the soil;
- **fine texture** (log variance of the log brightness over 3x3 pixels, averaged over 5x5): a water surface is
  flat, soil and vegetation have texture at the scale of a few centimetres. Taken on the lower envelope of the
  brightness (each pixel at most its 3x3 median), so bright specks (glint, foam) do not read as texture; the log
  makes it blind to exposure, shadow and white balance, which scale a region's pixels alike.

The cues are standardised over the frame and summed with fixed signs (water: bluer, less saturated, brighter,
smoother; texture and chromaticity weighted alike), and the minimum-error threshold of Kittler and Illingworth
(1986) splits the sum: unlike Otsu's, it does not pull the threshold into the larger class when the water is a
corner of the frame. A cloud shadow is darker and bluer, so brightness and chromaticity cancel across its edge.

Sun glint is the brightest, whitest and roughest part of the frame and can become a class of its own: when the
high class is rougher than the low one, it is glint on water, kept as water, and the rest is split again.

The split is accepted when the water class is clearly smoother than the land class and smooth in absolute terms
(the log variance of a flat surface under the camera's noise); otherwise the frame is one class, water when it is
that smooth. An accepted split's shore is also placed again by colour (:mod:`vehicle_agents.perception.shore`): the
texture's window puts the split's boundary 1-3 px into the water; what the drone reports of the shore is read there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

from vehicle_agents.perception.shore import colour_score

MIN_TEXTURE_CONTRAST = 0.9
"""The water class must be smoother than the land class by this much in median log variance (a factor 2.5)."""
WATER_TEXTURE_MAX = -7.8
"""Median log variance of the log brightness over 3x3 pixels below which ground is flat enough to be water."""
COARSE_WATER_TEXTURE_MAX = -3.2
"""... and whose median log coefficient of variation over 7x7 pixels is below this (a frame of one class)."""
MIN_SPLIT_FRACTION = 0.005
"""Each class of an accepted split covers at least this share of the frame."""
MIN_ENCLOSED_FRACTION = 0.02
"""A class under this share of the frame that touches no side of the frame is not the flood's edge: a flood is
larger than the footprint, so its water reaches the frame's side; a blob wholly inside (a smooth patch of soil
in grass, a puddle) makes the frame one class."""
GLINT_ROUNDS = 2
"""How many times a rougher high class is taken as glint on water and the rest split again."""
SCORE_SIGNS = np.array([1.0, -1.0, -1.0, 1.0], np.float32)
"""Signs of the standardised chromaticity, saturation, texture and brightness in the water score."""
_COLOUR_CUES = np.array([0, 1, 3])
"""The cues the colour score weighs (chromaticity, saturation, brightness), in the order of ``COLOUR_SIGNS``."""
TEXTURE_LEVELS_PER_UNIT = 16.0
TEXTURE_OFFSET = 16.0
"""Texture to 8 bits for its histograms: ``(log variance + 16) · 16`` (log variances -16..0; flat ground is near
-9, soil near -7)."""
_KERNEL3 = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (3, 3))
_KERNEL5 = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (5, 5))
_SUM_ROW_3 = np.array([[1.0, 1.0, 1.0, 9.0]], np.float32)
_BLUE_ROW_3 = np.array([[1.0, 0.0, 0.0, 3.0]], np.float32)
_LEVELS = np.arange(256.0)
_LEVEL_POWERS = np.stack((np.ones(256), _LEVELS, _LEVELS * _LEVELS))
"""(3, 256): a histogram times these rows gives each level's count, sum and sum of squares."""
_LOG_TABLE = np.log(np.arange(256, dtype=np.float32) + 1.0).reshape(1, 256)


def cue_stack(smooth: NDArray[np.uint8], grey8: NDArray[np.uint8]) -> NDArray[np.float32]:
    """(H/2, W/2, 4) float32 at half resolution: chromaticity, saturation, fine texture, log brightness (see the
    module) of the 3x3-median frame ``smooth`` and its grey ``grey8``. The texture is taken at full resolution (its
    scale is the pixel), then every cue is averaged over 2x2 pixels and smoothed over 3x3 of those (about 6x6
    pixels of the frame)."""
    log_envelope = cv2.LUT(cv2.min(grey8, cv2.medianBlur(grey8, 3)), _LOG_TABLE)
    mean = cv2.blur(log_envelope, (3, 3))
    texture = cv2.sqrBoxFilter(log_envelope, cv2.CV_32F, (3, 3))
    cv2.subtract(texture, cv2.multiply(mean, mean, dst=mean), dst=texture)
    cv2.log(cv2.max(texture, 1e-6, dst=texture), dst=texture)
    half = (smooth.shape[1] // 2, smooth.shape[0] // 2)
    small = cv2.resize(smooth, half, interpolation=cv2.INTER_AREA)
    small_float = small.astype(np.float32)
    total = cv2.transform(small_float, _SUM_ROW_3)
    chromaticity = cv2.divide(cv2.transform(small_float, _BLUE_ROW_3), total)
    _, hsv_saturation, value = cv2.split(cv2.cvtColor(small, cv2.COLOR_BGR2HSV))
    spread = cv2.multiply(hsv_saturation, value, scale=1.0 / 255.0, dtype=cv2.CV_32F)  # max − min of B, G, R
    saturation = cv2.divide(spread, total, dtype=cv2.CV_32F)
    brightness = cv2.LUT(cv2.cvtColor(small, cv2.COLOR_BGR2GRAY), _LOG_TABLE)
    cues = cv2.merge([chromaticity, saturation, cv2.resize(texture, half, interpolation=cv2.INTER_AREA), brightness])
    return cv2.blur(cues, (3, 3))


def minimum_error_threshold(score8: NDArray[np.uint8], mask: NDArray[np.uint8] | None = None) -> int | None:
    """Kittler-Illingworth threshold of an 8-bit image (pixels under ``mask`` only): the level t minimising
    ``P1 ln(σ1² / P1²) + P2 ln(σ2² / P2²)`` for the classes ≤ t and > t (two Gaussians fitted to the histogram;
    counts instead of shares only add a constant). None when no split leaves both classes a spread.

    Both classes' count, sum and sum of squares are rows of one (3, 2, levels) array, so each step of the
    criterion is one array operation for both classes (the cost is per operation at 256 levels, not per level)."""
    hist = cv2.calcHist([score8], [0], mask, [256], [0, 256]).reshape(1, 256)
    cumulative = (hist * _LEVEL_POWERS).cumsum(axis=1)
    n1 = cumulative[0]
    total = float(n1[-1])
    if total <= 0.0:
        return None
    least = 0.002 * total
    # Each class holds more than ``least`` pixels on one run of levels, found by bisection: n1 grows with the level
    # and n2 = total − n1 shrinks (the counts are whole numbers, so n2 > least exactly when n1 < total − least).
    first, end = int(n1.searchsorted(least, "right")), int(n1.searchsorted(total - least, "left"))
    if first >= end:
        return None
    classes = np.empty((3, 2, end - first))
    below = cumulative[:, first:end]
    classes[:, 0] = below
    np.subtract(cumulative[:, -1:], below, out=classes[:, 1])
    count = classes[0]
    mean = classes[1] / count
    var = classes[2] / count - mean ** 2
    spread = (var[0] > 0.5) & (var[1] > 0.5)
    terms = count * np.log(np.maximum(var, 0.5) / (count * count))
    cost = terms[0] + terms[1]
    cost[~spread] = np.inf
    level = int(cost.argmin())
    return first + level if math.isfinite(cost[level]) else None


def _score8(score: NDArray[np.float32], keep: NDArray[np.uint8] | None) -> NDArray[np.uint8]:
    """The score stretched to 8 bits over the pixels kept (the others clip), lightly smoothed."""
    low, high, _, _ = cv2.minMaxLoc(score, mask=keep)
    scale = 255.0 / max(high - low, 1e-6)
    return cv2.blur(cv2.convertScaleAbs(score, alpha=scale, beta=-low * scale), (3, 3))


def _texture_medians(texture8: NDArray[np.uint8], high: NDArray[np.uint8]) -> tuple[float, float, float]:
    """Median texture [log variance] of the high class, of the low class and of the whole frame, from 8-bit
    histograms (``TEXTURE_LEVELS_PER_UNIT`` levels per unit of log variance). ``high`` is 0 or 255 per pixel, so one
    two-dimensional histogram with two bins along it holds the low and the high class's histograms."""
    by_class = cv2.calcHist([texture8, high], [0, 1], None, [256, 2], [0, 256, 0, 256]).cumsum(axis=0)
    low_cumulative, high_cumulative = by_class[:, 0], by_class[:, 1]
    medians = []
    for cumulative in (high_cumulative, low_cumulative, low_cumulative + high_cumulative):
        level = int(cumulative.searchsorted(0.5 * cumulative[-1])) if cumulative[-1] > 0 else 255
        medians.append(level / TEXTURE_LEVELS_PER_UNIT - TEXTURE_OFFSET)
    return medians[0], medians[1], medians[2]


def _split(score: NDArray[np.float32], texture: NDArray[np.float32]
           ) -> tuple[NDArray[np.uint8], int | None, NDArray[np.uint8] | None]:
    """(8-bit score, threshold or None, its high class or None when not formed): the minimum-error split, with glint
    taken out of it. A high class rougher than the low one is glint; the score is stretched again over the rest (so
    the glint saturates at 255 and stays on the water side) and split again."""
    score8 = _score8(score, None)
    threshold = minimum_error_threshold(score8)
    high = None
    for _ in range(GLINT_ROUNDS):
        if threshold is None:
            break
        high = cv2.compare(score8, threshold, cv2.CMP_GT)
        n_high = cv2.countNonZero(high)
        if n_high == 0 or n_high > 0.95 * high.size:
            break
        low = cv2.bitwise_not(high)
        if cv2.mean(texture, mask=high)[0] <= cv2.mean(texture, mask=low)[0]:
            break
        stretched = _score8(score, low)
        found = minimum_error_threshold(stretched, low)
        if found is None:
            break
        score8, threshold, high = stretched, found, None
    return score8, threshold, high


@dataclass(frozen=True)
class ShoreByColour:
    """What places an accepted split's shore again by colour: the frame's (H, W) colour score
    (:func:`vehicle_agents.perception.shore.colour_score`, the split's signs and spreads), read along the split's
    boundary steps (:func:`vehicle_agents.perception.shore.shore_along_steps`)."""

    score: NDArray[np.float32]


def grey_water_with_shore(image_bgr: NDArray[np.uint8]
                          ) -> tuple[NDArray[np.bool_] | None, NDArray[np.uint8], float, ShoreByColour | None]:
    """(water mask or None for a one-class frame, 8-bit score, threshold, shore placed by colour) for a valid
    (H, W, 3) uint8 image; a one-class frame's threshold puts the frame's mean score above it when the frame is water.
    The split is found at half resolution; the mask is the full-resolution (bilinear) score over the same threshold.
    The shore is None for a one-class frame."""
    smooth = cv2.medianBlur(image_bgr, 3)
    grey8 = cv2.cvtColor(smooth, cv2.COLOR_BGR2GRAY)
    cues = cue_stack(smooth, grey8)
    mean, std = cv2.meanStdDev(cues)
    weights = SCORE_SIGNS / (std.ravel().astype(np.float32) + 1e-9)
    matrix = np.empty((1, 5), np.float32)
    matrix[0, :4] = weights
    matrix[0, 4] = -float(weights @ mean.ravel().astype(np.float32))
    score = cv2.transform(cues, matrix)
    texture = np.ascontiguousarray(cues[..., 2])
    score8, threshold, high = _split(score, texture)
    texture8 = cv2.convertScaleAbs(texture, alpha=TEXTURE_LEVELS_PER_UNIT, beta=TEXTURE_OFFSET * TEXTURE_LEVELS_PER_UNIT)
    full = cv2.resize(score8, (image_bgr.shape[1], image_bgr.shape[0]), interpolation=cv2.INTER_LINEAR)
    if high is None:
        high = cv2.compare(score8, threshold if threshold is not None else 255, cv2.CMP_GT)
    water_tex, land_tex, frame_tex = _texture_medians(texture8, high)
    if threshold is not None:
        water = _open_close(cv2.threshold(full, threshold, 1, cv2.THRESH_BINARY)[1])
        fraction = cv2.countNonZero(water) / water.size
        inside = MIN_SPLIT_FRACTION <= fraction <= 1.0 - MIN_SPLIT_FRACTION and (
            min(fraction, 1.0 - fraction) >= MIN_ENCLOSED_FRACTION or _small_class_reaches_side(water, fraction))
        if inside and land_tex - water_tex >= MIN_TEXTURE_CONTRAST and water_tex < WATER_TEXTURE_MAX:
            colour_weights = weights[_COLOUR_CUES]  # the colour cues' signs are the score's
            shore = ShoreByColour(colour_score(smooth, cv2.LUT(grey8, _LOG_TABLE), colour_weights))
            return water.view(bool), full, threshold + 0.5, shore
        if not inside:
            frame_tex = water_tex if fraction > 0.5 else land_tex
    mean_score = float(cv2.mean(full)[0])
    water = frame_tex < WATER_TEXTURE_MAX and coarse_texture(image_bgr) < COARSE_WATER_TEXTURE_MAX
    return None, full, mean_score - 1.0 if water else mean_score + 1.0, None


def _open_close(water: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """A 0/1 mask without specks: opened 3x3 (stray water pixels), then closed 5x5 (stray land pixels)."""
    return cv2.morphologyEx(cv2.morphologyEx(water, cv2.MORPH_OPEN, _KERNEL3), cv2.MORPH_CLOSE, _KERNEL5)


def _small_class_reaches_side(water: NDArray[np.uint8], fraction: float) -> bool:
    """Whether the smaller class of a 0/1 water mask holding ``fraction`` water has a pixel on a side of the frame."""
    sides = (water[0], water[-1], water[:, 0], water[:, -1])
    if fraction <= 0.5:
        return any(bool(side.any()) for side in sides)
    return not all(bool(side.all()) for side in sides)


def coarse_texture(image_bgr: NDArray[np.uint8]) -> float:
    """Median log coefficient of variation of the brightness over 7x7 windows, on its lower envelope (each pixel at
    most its 3x3 median, so glint and foam specks do not count): land seen from close up (its fine texture blurred
    over several pixels) still has patches at this scale; water has none."""
    grey8 = cv2.cvtColor(image_bgr, cv2.COLOR_BGR2GRAY)
    grey = cv2.min(grey8, cv2.medianBlur(grey8, 3)).astype(np.float32)
    mean = cv2.blur(grey, (7, 7))
    variance = cv2.max(cv2.subtract(cv2.sqrBoxFilter(grey, cv2.CV_32F, (7, 7)), cv2.multiply(mean, mean)), 0.25)
    log_cv = cv2.subtract(cv2.multiply(cv2.log(variance), 0.5), cv2.log(mean + 1.0))
    return float(np.median(log_cv[::2, ::2]))
