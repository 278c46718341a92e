"""Where exactly the shore lies, once the frame has been split into water and land.

The grey-water split is found on cues averaged over about 6x6 pixels, and one of them, the fine texture, is a
windowed statistic: a window that straddles the shore holds the step between the two colours and reads as rough,
so the shore reads as land on both sides and the split's boundary lands one to three pixels into the water (a
bias, not noise: 0.1-0.2 m at 10 m, every edge point inside the flood). Colour has no such window. So the shore is
placed again from the colour cues alone (chromaticity, saturation, brightness of the 3x3-median image, standardised
and signed as in the split), along each step of the split's boundary (:mod:`vehicle_agents.perception.boundary_steps`:
a water pixel beside a land pixel, along a row or down a column): the samples within ``BAND_PX`` of the step on
that line are classified by their colour score against the level half-way between the water and the land seen
just beyond the band (``BAND_PX`` to ``RING_PX`` from the step on each side, over all the steps, on pixels the split
put on that side), and the shore point lies after as many samples from the water end as read water, at the sub-pixel
crossing of the half-way level. A step between two colours, however blurred, crosses its half-way level where the
step is, and the two levels are measured beside this frame's shore (wet soil, shadow and exposure included), never
assumed. Counting the samples instead of looking for the first crossing keeps one noisy sample from moving the
point. The band is longer than the split's bias because a row or column crosses a slanting shore at a slant: a
shore 4 px away across it can lie 5-6 px away along the line.

No shore is placed when either side's ring holds too few samples or the colour does not tell the two sides apart
there (water not above land in the colour score): the split's boundary stands.
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import NDArray

from vehicle_agents.perception.boundary_steps import BoundarySteps

BAND_PX = 5
"""Samples this many pixels or fewer beyond a step's own two pixels, along its line, are classified by colour."""
RING_PX = 10
"""The water and land levels are the mean colour scores of the samples beyond ``BAND_PX`` up to this far."""
MIN_RING_SAMPLES = 10
"""Each side's ring must hold at least this many samples for its level to be trusted."""
COLOUR_SIGNS = np.array([1.0, -1.0, 1.0], np.float32)
"""Signs of the standardised chromaticity, saturation and log brightness in the colour score (water positive)."""
_OFFSETS = np.arange(-RING_PX, RING_PX + 2, dtype=np.int32)
"""Sample positions along a step's line, from its water pixel (0) towards its land pixel (1)."""
_RING_SAMPLES = RING_PX - BAND_PX
"""The first and the last this many samples of a line are its water and its land ring."""
_BAND = slice(_RING_SAMPLES, _RING_SAMPLES + 2 * BAND_PX + 2)
"""The band's samples: offsets -BAND_PX .. BAND_PX + 1."""
_BAND_SAMPLES = 2 * BAND_PX + 2
_LINE_SAMPLES = _OFFSETS.size
_ONES_BAND = np.ones(_BAND_SAMPLES, np.int32)
_PAD = RING_PX + 2
"""The frame is padded this wide so that no sample along a step's line falls outside it."""
_LINE_STEPS = np.stack((1 - _OFFSETS, _OFFSETS))
"""Sample positions along a step's line in strides from its first pixel, by whether that pixel is water (row 1:
the line starts there) or land (row 0: the water pixel is the second one, and the line runs back over the first)."""
_LAST_SAMPLE = np.clip(np.arange(_BAND_SAMPLES + 1) - 1, 0, _BAND_SAMPLES - 2)
"""By the number of band samples that read water: the band sample before the crossing (the pair it lies between
starts there)."""
_ALONG_BASE = np.concatenate(([-BAND_PX - 0.5], _LAST_SAMPLE[1:-1] - BAND_PX, [BAND_PX + 1.5]))
_ALONG_FRACTION = np.concatenate(([0.0], np.ones(_BAND_SAMPLES - 1), [0.0]))
"""By the number of band samples that read water: the point's offset from the water pixel is the base plus the
crossing's fraction times this (a band all water or all land puts the point half a pixel beyond its end)."""
_CROSSING_PAIR = np.array([_RING_SAMPLES, _RING_SAMPLES + 1])
_SUM_ROW = np.array([[1.0, 1.0, 1.0, 9.0]], np.float32)


def colour_score(smooth_bgr: NDArray[np.uint8], log_grey: NDArray[np.float32], weights: NDArray[np.float32]
                 ) -> NDArray[np.float32]:
    """(H, W) float32 colour score of the 3x3-median frame: ``weights`` (chromaticity, saturation, log brightness)
    times chromaticity ``(B + 3) / (B + G + R + 9)``, saturation ``(max − min) / (B + G + R + 9)`` and log
    brightness ``log_grey``: the grey-water cues without the texture, summed in one pass per term."""
    as_float = smooth_bgr.astype(np.float32)
    blue, green, red = cv2.split(smooth_bgr)
    high = cv2.max(blue, green)
    low = cv2.min(blue, green)
    cv2.max(high, red, dst=high)
    cv2.min(low, red, dst=low)
    spread = cv2.subtract(high, low, dst=high).astype(np.float32)
    score = cv2.transform(as_float, np.array([[weights[0], 0.0, 0.0, 3.0 * weights[0]]], np.float32))
    cv2.scaleAdd(spread, float(weights[1]), score, dst=score)
    cv2.divide(score, cv2.transform(as_float, _SUM_ROW), dst=score)
    return cv2.scaleAdd(log_grey, float(weights[2]), score, dst=score)


def shore_along_steps(steps: BoundarySteps, water: NDArray[np.uint8], score: NDArray[np.float32]
                      ) -> NDArray[np.float64] | None:
    """(K, 2) image (x, y) [px] of the shore placed by colour along each of ``steps`` (see the module), or None
    when the colour cannot place it. ``water`` is the split's (H, W) 0/1 mask, ``score`` the frame's colour score
    (:func:`colour_score`, water high). Samples beyond the frame's side read the score of the pixel on the side and
    belong to neither ring."""
    padded_score = cv2.copyMakeBorder(score, _PAD, _PAD, _PAD, _PAD, cv2.BORDER_REPLICATE).reshape(-1)
    padded_water = cv2.copyMakeBorder(water, _PAD, _PAD, _PAD, _PAD, cv2.BORDER_CONSTANT, value=2).reshape(-1)
    padded_width = water.shape[1] + 2 * _PAD
    first = steps.first_px
    along_x = steps.along_x
    count = first.shape[0]
    first_flat = first @ np.array([1, padded_width], np.int32) + _PAD * (padded_width + 1)
    stride = np.full(count, padded_width, np.int32)
    stride[:along_x] = 1
    water_first = padded_water[first_flat]
    flat = first_flat[:, None] + stride[:, None] * _LINE_STEPS[water_first]
    samples = padded_score[flat]
    side = padded_water[flat]
    water_ring = samples[:, :_RING_SAMPLES][side[:, :_RING_SAMPLES] == 1]
    land_ring = samples[:, -_RING_SAMPLES:][side[:, -_RING_SAMPLES:] == 0]
    if water_ring.size < MIN_RING_SAMPLES or land_ring.size < MIN_RING_SAMPLES:
        return None
    water_level = float(water_ring.sum()) / water_ring.size
    land_level = float(land_ring.sum()) / land_ring.size
    if water_level <= land_level:
        return None
    threshold = np.float32(0.5 * (water_level + land_level))
    n_water = (samples[:, _BAND] > threshold).view(np.uint8) @ _ONES_BAND
    pair = samples.reshape(-1)[(np.arange(0, count * _LINE_SAMPLES, _LINE_SAMPLES) + _LAST_SAMPLE[n_water])[:, None]
                               + _CROSSING_PAIR]
    a, b = pair[:, 0], pair[:, 1]
    frac = np.divide(threshold - a, b - a, out=np.full(count, 0.5, np.float32), where=b != a)
    along = _ALONG_BASE[n_water] + _ALONG_FRACTION[n_water] * np.minimum(np.maximum(frac, 0.25), 0.75)
    shift = np.where(water_first.view(bool), along, 1.0 - along)
    point = first + 0.5
    point[:along_x, 0] += shift[:along_x]
    point[along_x:, 1] += shift[along_x:]
    return point
