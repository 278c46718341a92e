"""Which pixels of a downward frame are water, without a fixed colour of water.

Two cues, tried in turn:

- **Water under a blue sky is bluer than grey**, vegetation and soil yellower: the blueness ``B − (G + R)/2``
  (tried first; it is exact where it applies and costs one transform). Otsu's split, moved half-way between the
  class means, with specks removed by an opening and a closing, and floating debris (small land patches the water
  encloses) taken as water when the ground sample is known (:mod:`vehicle_agents.perception.water_holes`).
- **Water that is not blue** (silt-laden, grey sky, cloud shadow): lighter, less saturated, bluer in chromaticity
  and smoother than the land beside it (:mod:`vehicle_agents.perception.grey_water`).
"""

from __future__ import annotations

import math

import cv2
import numpy as np
from numpy.typing import NDArray

from vehicle_agents.perception.grey_water import ShoreByColour, grey_water_with_shore
from vehicle_agents.perception.water_holes import fill_small_land_holes

NEUTRAL_BLUENESS = 128.0
"""Blueness ``B − (G + R)/2 + 128`` of grey: water under a blue sky lies above it, vegetation and soil below."""
MAX_THRESHOLD_SHIFT = 16.0
"""A blueness split further than this from neutral [DN] is inside one class (grass against dry grass)."""
MIN_BLUENESS_SEPARATION = 10.0
"""Otsu's two blueness classes must differ by this much in mean [DN] to be two kinds of ground."""
MIN_BLUE_SPLIT_FRACTION = 0.02
"""A blueness split leaving less than this share of the frame to a class is checked by the grey-water cue
(sun glint on brown water is white specks whose blueness can reach neutral) ..."""
MIN_SLIVER_BLUENESS = 12.0
"""... unless the small class is clearly blue: this far above neutral on average [DN] (water mirroring a blue
sky lies 20-35 above it)."""
_KERNEL3 = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (3, 3))
_MAX_TWICE_WITHOUT_BLUE = -2.0 * MAX_THRESHOLD_SHIFT + 1.0
"""``2B − G − R`` at or below this rounds (half to even) to a blueness of at most ``NEUTRAL_BLUENESS −
MAX_THRESHOLD_SHIFT``, below any threshold the blue cue uses: −31 halves to −15.5, which rounds to −16."""


def segment_water(image_bgr: NDArray[np.uint8], ground_sample_m: float = math.nan
                  ) -> tuple[NDArray[np.bool_] | None, NDArray[np.uint8], float]:
    """:func:`segment_water_with_shore` without the shore placed by colour."""
    mask, score, threshold, _ = segment_water_with_shore(image_bgr, ground_sample_m)
    return mask, score, threshold


def segment_water_with_shore(image_bgr: NDArray[np.uint8], ground_sample_m: float = math.nan
                             ) -> tuple[NDArray[np.bool_] | None, NDArray[np.uint8], float, ShoreByColour | None]:
    """(water mask or None for a one-class frame, score image, threshold) for a valid (H, W, 3) uint8 image.

    Water is the high side of the threshold on the score: the blueness when the frame's water mirrors a blue sky
    (a split leaving each class at least ``MIN_BLUE_SPLIT_FRACTION`` of the frame, or a small class that is clearly
    blue), else the grey-water score of :mod:`vehicle_agents.perception.grey_water`. A one-class frame returns None
    as mask with a threshold that puts the frame's mean score above it when the frame is water (a frame all bluer
    than neutral is water). A faint blue sliver
    the grey cue cannot see (it calls the frame land) is kept: glint, the other small near-blue thing in a frame,
    lies on water the grey cue finds. ``ground_sample_m`` [m/px], when given, lets the blue cue take the floating
    debris inside its water as water (:func:`vehicle_agents.perception.water_holes.fill_small_land_holes`). The
    fourth item is the grey-water split's shore placed again by colour (None for the blue cue, which has no bias).
    """
    blue = _blue_water(image_bgr, ground_sample_m)
    if blue is not None and blue[0] is None:
        return (*blue, None)
    if blue is not None and blue[0] is not None:
        water = blue[0].view(np.uint8)
        fraction = cv2.countNonZero(water) / water.size
        if (MIN_BLUE_SPLIT_FRACTION <= fraction <= 1.0 - MIN_BLUE_SPLIT_FRACTION
                or cv2.mean(blue[1], mask=water)[0] >= NEUTRAL_BLUENESS + MIN_SLIVER_BLUENESS):
            return (*blue, None)
    grey = grey_water_with_shore(image_bgr)
    if grey[0] is None and blue is not None and blue[0] is not None and float(cv2.mean(grey[1])[0]) < grey[2]:
        return (*blue, None)
    return grey


def _twice_blueness(image_bgr: NDArray[np.uint8]) -> NDArray[np.int16]:
    """``2B − G − R`` per pixel in 16-bit integers (exact): twice the blueness without its offset."""
    blue, green, red = cv2.split(image_bgr)
    return cv2.subtract(cv2.add(blue, blue, dtype=cv2.CV_16S), cv2.add(green, red, dtype=cv2.CV_16S))


def _blueness(image_bgr: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """``B − (G + R)/2 + 128`` per pixel, rounded half to even and saturated to 8 bits: ``2B − G − R`` in 16-bit
    integers, halved and offset in one conversion (the same bytes as the floating-point transform, on all 2^24
    colours, at two thirds of its cost)."""
    return _halved_blueness(_twice_blueness(image_bgr))


def _halved_blueness(twice: NDArray[np.int16]) -> NDArray[np.uint8]:
    return cv2.addWeighted(twice, 0.5, twice, 0.0, NEUTRAL_BLUENESS, dtype=cv2.CV_8U)


def _blue_water(image_bgr: NDArray[np.uint8], ground_sample_m: float
                ) -> tuple[NDArray[np.bool_] | None, NDArray[np.uint8], float] | None:
    """Clear or murky water under a blue sky: the blueness ``B − (G + R)/2 + 128`` is above neutral grey for water
    and below it for vegetation and soil (lighting scales every channel alike, so the sign holds in shade and sun).
    Otsu's split is moved half-way between the class means, or to neutral when that lies far from it (Otsu split
    grass from dry grass beside a sliver of water); a frame whose pixels are all above neutral is water. None when
    the frame holds no blue water (the other cue decides)."""
    twice = _twice_blueness(image_bgr)
    if cv2.minMaxLoc(twice)[1] <= _MAX_TWICE_WITHOUT_BLUE:
        return None  # no pixel can be above any threshold this cue would use: no blue water
    blueness = _halved_blueness(twice)
    _, binary = cv2.threshold(blueness, 0, 1, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
    n = binary.size
    n_high = cv2.countNonZero(binary)
    mean_all = cv2.mean(blueness)[0]
    if n_high in (0, n):
        return (None, blueness, NEUTRAL_BLUENESS) if mean_all > NEUTRAL_BLUENESS else None
    mean_high = cv2.mean(blueness, mask=binary)[0]
    mean_low = (mean_all * n - mean_high * n_high) / (n - n_high)
    if mean_high - mean_low < MIN_BLUENESS_SEPARATION:
        return (None, blueness, NEUTRAL_BLUENESS) if mean_all > NEUTRAL_BLUENESS else None
    threshold = 0.5 * (mean_low + mean_high)
    if abs(threshold - NEUTRAL_BLUENESS) > MAX_THRESHOLD_SHIFT:
        threshold = NEUTRAL_BLUENESS
    _, binary = cv2.threshold(blueness, threshold, 1, cv2.THRESH_BINARY)
    n_high = cv2.countNonZero(binary)
    if n_high == n:
        return None, blueness, NEUTRAL_BLUENESS
    if n_high == 0:
        return None
    binary = cv2.morphologyEx(binary, cv2.MORPH_OPEN, _KERNEL3)
    binary = cv2.morphologyEx(binary, cv2.MORPH_CLOSE, _KERNEL3)
    water = binary.view(bool)
    if math.isfinite(ground_sample_m):
        water = fill_small_land_holes(water, ground_sample_m)
    return water, blueness, float(threshold)
