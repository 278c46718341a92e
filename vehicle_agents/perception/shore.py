"""Where exactly the shore lies, once the frame has been split into water and land.

The grey-water split is found on cues averaged over about 6x6 pixels, and one of them, the fine texture, is a
windowed statistic: a window that straddles the shore holds the step between the two colours and reads as rough,
so the shore reads as land on both sides and the split's boundary lands one to three pixels into the water (a
bias, not noise: 0.1-0.2 m at 10 m, the whole ring drawn inside the flood). Colour has no such window. So the
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
_LOG_LEVELS = np.log(np.arange(256, dtype=np.float32) + np.float32(1.0))


def colour_scores(smooth_bgr: NDArray[np.uint8], grey8: NDArray[np.uint8], flat_index: NDArray[np.intp]
                  ) -> list[NDArray[np.float32]]:
    """Chromaticity ``(B + 3) / (B + G + R + 9)``, saturation ``(max − min) / (B + G + R + 9)`` and log brightness,
    each a (K,) float32 array over the listed pixels (indices into the flattened frame) of the 3x3-median image:
    the grey-water cues without the texture. Only the pixels near the shore are asked for."""
    blue, green, red = (plane.reshape(-1)[flat_index] for plane in cv2.split(smooth_bgr))
    total = blue.astype(np.float32)
    total += green
    total += red
    total += np.float32(9.0)
    spread = np.maximum(np.maximum(blue, green), red) - np.minimum(np.minimum(blue, green), red)
    return [np.divide(blue + np.float32(3.0), total), np.divide(spread, total, dtype=np.float32),
            _LOG_LEVELS[grey8.reshape(-1)[flat_index]]]


def refine_shore(coarse: NDArray[np.uint8], smooth_bgr: NDArray[np.uint8], grey8: NDArray[np.uint8]
                 ) -> tuple[NDArray[np.uint8], NDArray[np.float32], float] | None:
    """(water mask 0/1, colour score image, its threshold) with the shore placed by colour near ``coarse``'s
    boundary, or None when the colour cannot place it (see the module). ``coarse`` is the split's (H, W) 0/1 mask,
    ``smooth_bgr`` the 3x3-median frame and ``grey8`` its grey. The score image holds the threshold itself beyond
    ``RING_PX`` of the boundary, where it is not computed."""
    near_outside = cv2.dilate(coarse, _BAND)
    near_inside = cv2.erode(coarse, _BAND)
    zone = np.flatnonzero(cv2.subtract(cv2.dilate(coarse, _RING), cv2.erode(coarse, _RING)))
    outside, inside = near_outside.reshape(-1)[zone], near_inside.reshape(-1)[zone]
    water_ring, land_ring = inside == 1, outside == 0
    if np.count_nonzero(water_ring) < MIN_RING_PX or np.count_nonzero(land_ring) < MIN_RING_PX:
        return None
    score = np.zeros(zone.size, np.float32)
    for sign, cue in zip(COLOUR_SIGNS, colour_scores(smooth_bgr, grey8, zone)):
        score += cue * (sign / (cue.std() + np.float32(1e-9)))
    water_level = float(score[water_ring].mean())
    land_level = float(score[land_ring].mean())
    if water_level <= land_level:
        return None
    threshold = 0.5 * (water_level + land_level)
    band = outside != inside
    refined = coarse.copy()
    refined.reshape(-1)[zone[band]] = score[band] > threshold
    score_image = np.full(coarse.shape, threshold, np.float32)
    score_image.reshape(-1)[zone] = score
    return refined, score_image, threshold
