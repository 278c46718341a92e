"""Where exactly the shore lies, once the frame has been split into water and land.

The grey-water split is found on cues averaged over about 6x6 pixels, and one of them, the fine texture, is a
windowed statistic: a window that straddles the shore holds the step between the two colours and reads as rough,
so the shore reads as land on both sides and the split's boundary lands one to three pixels into the water (a
bias, not noise: 0.1-0.2 m at 10 m, every edge point inside the flood). Colour has no such window. So the
boundary is placed again at full resolution from the colour cues alone (chromaticity, saturation, brightness of
the 3x3-median image, standardised and signed as in the split), within ``BAND_PX`` of the split's boundary:
a pixel there is water when its colour score is above the level half-way between the water and the land seen
just beyond the band (``BAND_PX`` to ``RING_PX`` from the boundary, on each side). A step between two colours,
however blurred, crosses its half-way level where the step is, and the two levels are measured beside this
frame's shore (wet soil, shadow and exposure included), never assumed.

No refinement is made when either side's ring is nearly empty or the colour does not tell the two sides apart
there (water not above land in the colour score): the split's boundary stands.
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import NDArray

BAND_PX = 3
"""Pixels within this distance of the split's boundary (Chebyshev) are classified again by colour."""
RING_PX = 8
"""The water and land levels are the mean colour scores from ``BAND_PX`` to this distance of the boundary."""
MIN_RING_PX = 10
"""Each side's ring must hold at least this many pixels for its level to be trusted."""
COLOUR_SIGNS = np.array([1.0, -1.0, 1.0], np.float32)
"""Signs of the standardised chromaticity, saturation and log brightness in the colour score (water positive)."""
_BAND = cv2.getStructuringElement(cv2.MORPH_RECT, (2 * BAND_PX + 1, 2 * BAND_PX + 1))
_RING = cv2.getStructuringElement(cv2.MORPH_RECT, (2 * RING_PX + 1, 2 * RING_PX + 1))
_SUM_ROW = np.array([[1.0, 1.0, 1.0, 9.0]], np.float32)


def colour_score(smooth_bgr: NDArray[np.uint8], log_grey: NDArray[np.float32], weights: NDArray[np.float32]
                 ) -> NDArray[np.float32]:
    """(H, W) float32 colour score of the 3x3-median frame: ``weights`` (chromaticity, saturation, log brightness)
    times chromaticity ``(B + 3) / (B + G + R + 9)``, saturation ``(max − min) / (B + G + R + 9)`` and log
    brightness ``log_grey``: the grey-water cues without the texture, summed in one pass per term."""
    as_float = smooth_bgr.astype(np.float32)
    blue, green, red = cv2.split(smooth_bgr)
    spread = cv2.subtract(cv2.max(cv2.max(blue, green), red), cv2.min(cv2.min(blue, green), red))
    numerator = cv2.transform(as_float, np.array([[weights[0], 0.0, 0.0, 3.0 * weights[0]]], np.float32))
    numerator = cv2.scaleAdd(spread.astype(np.float32), float(weights[1]), numerator)
    ratio = cv2.divide(numerator, cv2.transform(as_float, _SUM_ROW))
    return cv2.scaleAdd(log_grey, float(weights[2]), ratio)


def refine_shore(coarse: NDArray[np.uint8], smooth_bgr: NDArray[np.uint8], log_grey: NDArray[np.float32],
                 cue_std: NDArray[np.float32]) -> tuple[NDArray[np.uint8], NDArray[np.float32], float] | None:
    """(water mask 0/1, colour score, its threshold) with the shore placed by colour near ``coarse``'s boundary,
    or None when the colour cannot place it (see the module). ``coarse`` is the split's (H, W) 0/1 mask,
    ``smooth_bgr`` the 3x3-median frame, ``log_grey`` its log brightness, ``cue_std`` the spread of chromaticity,
    saturation and log brightness over the frame (to standardise them)."""
    near_outside = cv2.dilate(coarse, _BAND)
    near_inside = cv2.erode(coarse, _BAND)
    water_ring = cv2.subtract(near_inside, cv2.erode(coarse, _RING))
    land_ring = cv2.subtract(cv2.dilate(coarse, _RING), near_outside)
    if cv2.countNonZero(water_ring) < MIN_RING_PX or cv2.countNonZero(land_ring) < MIN_RING_PX:
        return None
    score = colour_score(smooth_bgr, log_grey, COLOUR_SIGNS / (cue_std + np.float32(1e-9)))
    water_level = cv2.mean(score, mask=water_ring)[0]
    land_level = cv2.mean(score, mask=land_ring)[0]
    if water_level <= land_level:
        return None
    threshold = 0.5 * (water_level + land_level)
    band = cv2.subtract(near_outside, near_inside)
    by_colour = cv2.bitwise_and(band, cv2.compare(score, threshold, cv2.CMP_GT))
    return cv2.bitwise_or(cv2.subtract(coarse, band), by_colour), score, float(threshold)
