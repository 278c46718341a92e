"""Which pixels of a downward frame are water, without a fixed colour of water.

Three physical cues:

- **Water under a blue sky is bluer than grey**, vegetation and soil yellower: the blueness ``B − (G + R)/2``
  (tried first; it is exact where it applies and costs one transform).
- **Water is smoother than land.** A water surface is flat; soil, grass and crops have texture at the scale of a
  few centimetres. The local coefficient of variation of the brightness (standard deviation over mean in a small
  window) measures it and does not change with exposure, shadow or white balance, which scale a region's pixels
  alike.
- **Water is less saturated than the land beside it.** Its surface mirrors the sky, which adds a grey component to
  whatever colour the water carries (murky or silt-laden tan), so the normalised blue chromaticity
  ``B / (B + G + R)`` of water lies above that of the soil it borders.

A frame without blue water is split by Otsu's method on the two last cues standardised over the frame and combined
(texture weighted most), and the split is accepted only when the smoother class is clearly smoother (a split
inside the land, soil against soil or sun against cloud shadow, has no such contrast); otherwise the frame is one
class, water if its texture is that of water. Small specks are removed by an opening and floating debris (rough
specks inside the water) by a closing.
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import NDArray

MIN_TEXTURE_CONTRAST = 0.5
"""The water class must be smoother than the land class by this much in mean log local coefficient of variation
(a factor 1.6)."""
WATER_TEXTURE_MAX = -3.5
"""A one-class frame whose mean log local coefficient of variation is below this is water (smooth)."""
NEUTRAL_BLUENESS = 128.0
"""Blueness ``B − (G + R)/2 + 128`` of grey: water under a blue sky lies above it, vegetation and soil below."""
MAX_THRESHOLD_SHIFT = 16.0
"""A blueness split further than this from neutral [DN] is inside one class (grass against dry grass)."""
MIN_BLUENESS_SEPARATION = 10.0
"""Otsu's two blueness classes must differ by this much in mean [DN] to be two kinds of ground."""
TEXTURE_WINDOW_PX = 7
"""Side of the window the local coefficient of variation is taken over for a one-class frame [px]."""
FINE_TEXTURE_WINDOW_PX = 3
"""The grey-water split's texture: the coefficient of variation over 3x3 pixels (sharp at the shore) ..."""
FINE_TEXTURE_BLUR_PX = 5
"""... averaged over 5x5 (steady inside each class)."""
TEXTURE_WEIGHT = 5.0
"""Weight of the standardised texture against the standardised chromaticity in the grey-water score."""
CHROMA_SCALE = 1024.0
CHROMA_OFFSET = 0.2
"""Chromaticity to 8 bits: ``(B / (B + G + R) − 0.2) · 1024``, so 0.2-0.45 spans the 256 levels (soil and turbid
water lie near 0.23-0.27), clipped beyond."""
_KERNEL3 = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (3, 3))
_KERNEL5 = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (5, 5))
_SUM_ROW = np.array([[1.0, 1.0, 1.0]], np.float32)
_BLUENESS_ROW = np.array([[1.0, -0.5, -0.5, 128.0]], np.float32)


def chromaticity_8u(image_bgr: NDArray[np.uint8]) -> NDArray[np.uint8]:
    """The normalised blue chromaticity ``B / (B + G + R)``, slightly smoothed, as 8 bits (see the constants)."""
    total = cv2.transform(image_bgr, _SUM_ROW)
    blue = cv2.extractChannel(image_bgr, 0)
    ratio = cv2.divide(blue, total + 3.0, dtype=cv2.CV_32F)
    ratio = cv2.blur(ratio, (3, 3))
    return cv2.convertScaleAbs(ratio, alpha=CHROMA_SCALE, beta=-CHROMA_OFFSET * CHROMA_SCALE)


def log_texture(image_bgr: NDArray[np.uint8], window_px: int = TEXTURE_WINDOW_PX) -> NDArray[np.float32]:
    """Log of the local coefficient of variation of the brightness over ``window_px`` windows."""
    grey = cv2.cvtColor(image_bgr, cv2.COLOR_BGR2GRAY).astype(np.float32)
    k = (window_px, window_px)
    mean = cv2.blur(grey, k)
    square = cv2.blur(cv2.multiply(grey, grey), k)
    variance = cv2.max(cv2.subtract(square, cv2.multiply(mean, mean)), 0.25)
    return cv2.subtract(cv2.multiply(cv2.log(variance), 0.5), cv2.log(mean + 1.0))


def segment_water(image_bgr: NDArray[np.uint8]) -> tuple[NDArray[np.bool_] | None, NDArray[np.uint8], float]:
    """(water mask or None for a one-class frame, score image, threshold) for a valid (H, W, 3) uint8 image.

    Water is the high side of the threshold on the score: the blueness when the frame's water mirrors a blue sky,
    else the chromaticity ``B / (B + G + R)``. A one-class frame returns None as mask with a threshold that puts
    the frame's mean score above it when the frame is water.
    """
    blue = _blue_water(image_bgr)
    if blue is not None:
        return blue
    return _grey_water(image_bgr)


def _blue_water(image_bgr: NDArray[np.uint8]) -> tuple[NDArray[np.bool_] | None, NDArray[np.uint8], float] | None:
    """Clear or murky water under a blue sky: the blueness ``B − (G + R)/2 + 128`` is above neutral grey for water
    and below it for vegetation and soil (lighting scales every channel alike, so the sign holds in shade and sun).
    Otsu's split is moved half-way between the class means, or to neutral when that lies far from it (Otsu split
    grass from dry grass beside a sliver of water); a frame whose pixels are all above neutral is water. None when
    the frame holds no blue water (the other cue decides)."""
    blueness = cv2.transform(image_bgr, _BLUENESS_ROW)
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
    return binary.view(bool), blueness, float(threshold)


def _grey_water(image_bgr: NDArray[np.uint8]) -> tuple[NDArray[np.bool_] | None, NDArray[np.uint8], float]:
    """Water that is not blue (silt-laden, grey sky): smoother and less saturated than the land beside it. Both
    cues are standardised over the frame and combined, texture weighted ``TEXTURE_WEIGHT`` times chromaticity (the
    more reliable cue where soil and water have nearly one colour); Otsu splits the combined score."""
    texture = log_texture(image_bgr)
    fine = cv2.blur(log_texture(image_bgr, FINE_TEXTURE_WINDOW_PX), (FINE_TEXTURE_BLUR_PX, FINE_TEXTURE_BLUR_PX))
    chroma = chromaticity_8u(image_bgr).astype(np.float32)
    (c_mean,), (c_std,) = cv2.meanStdDev(chroma)
    (t_mean,), (t_std,) = cv2.meanStdDev(fine)
    score = (chroma - np.float32(c_mean[0])) * np.float32(1.0 / (c_std[0] + 1e-6))
    score -= (fine - np.float32(t_mean[0])) * np.float32(TEXTURE_WEIGHT / (t_std[0] + 1e-6))
    score8 = cv2.normalize(score, None, 0, 255, cv2.NORM_MINMAX, cv2.CV_8U)
    threshold, binary = cv2.threshold(score8, 0, 1, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
    n = binary.size
    n_high = cv2.countNonZero(binary)
    if n_high in (0, n):
        return _one_class(score8, texture)
    tex_all = cv2.mean(fine)[0]
    tex_high = cv2.mean(fine, mask=binary)[0]
    tex_low = (tex_all * n - tex_high * n_high) / (n - n_high)
    if tex_low - tex_high < MIN_TEXTURE_CONTRAST:
        return _one_class(score8, texture)
    binary = cv2.morphologyEx(binary, cv2.MORPH_OPEN, _KERNEL3)
    binary = cv2.morphologyEx(binary, cv2.MORPH_CLOSE, _KERNEL5)
    return binary.view(bool), score8, float(threshold)


def _one_class(chroma: NDArray[np.uint8], texture: NDArray[np.float32]) -> tuple[None, NDArray[np.uint8], float]:
    """A frame of one kind of ground: water when it is smooth. The threshold returned puts the frame's mean
    score above it for water and below it for land."""
    mean = float(cv2.mean(chroma)[0])
    water = cv2.mean(texture)[0] < WATER_TEXTURE_MAX
    return None, chroma, mean - 1.0 if water else mean + 1.0
