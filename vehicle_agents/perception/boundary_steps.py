"""Where a water mask changes between 4-neighbours: the boundary as pixel steps, and each step's sub-pixel point.

A step is a pair of 4-neighbour pixels, one water and one land: along a row (pixels (x, y) and (x + 1, y)) or down
a column ((x, y) and (x, y + 1)). The edge points perception reports lie on these segments, where the score the
mask was thresholded on crosses its threshold; the colour shore (:mod:`vehicle_agents.perception.shore`) is
placed along the same steps' axes. Pure: a mask in, integer pixel pairs and points out.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class BoundarySteps:
    """A mask's steps: ``first_px`` (K, 2) the (x, y) of each pair's first pixel (left or upper); the first
    ``along_x`` pairs lie along a row, the rest down a column."""

    first_px: NDArray[np.int32]
    along_x: int

    def subset(self, keep: NDArray[np.bool_]) -> BoundarySteps:
        """The steps where ``keep`` (K,) is true, in their order."""
        return BoundarySteps(self.first_px[keep], int(np.count_nonzero(keep[: self.along_x])))


def boundary_steps(mask: NDArray[np.uint8]) -> BoundarySteps | None:
    """Every step of an (H, W) 0/1 mask, or None when the mask has none (one class)."""
    found = [cv2.findNonZero(cv2.bitwise_xor(mask[:, :-1], mask[:, 1:])),
             cv2.findNonZero(cv2.bitwise_xor(mask[:-1, :], mask[1:, :]))]
    parts = [f.reshape(-1, 2) for f in found if f is not None]
    if not parts:
        return None
    return BoundarySteps(np.concatenate(parts) if len(parts) > 1 else parts[0],
                         0 if found[0] is None else len(found[0]))


def step_points_px(steps: BoundarySteps, score: NDArray[np.generic], threshold: float) -> NDArray[np.float64]:
    """(K, 2) image (x, y) [px] of each step's point: on the segment between its two pixel centres, where ``score``
    crosses ``threshold`` (linear interpolation, clamped to the segment's middle half so a noisy pixel cannot throw
    it far)."""
    xy = steps.first_px
    along_x = steps.along_x
    width = score.shape[1]
    flat = score.reshape(-1)
    index = xy[:, 1] * width + xy[:, 0]
    a = flat[index].astype(np.float32)
    index[:along_x] += 1
    index[along_x:] += width
    b = flat[index].astype(np.float32)
    frac = np.divide(threshold - a, b - a, out=np.full_like(a, 0.5), where=b != a)
    np.maximum(frac, 0.25, out=frac)
    np.minimum(frac, 0.75, out=frac)
    point = xy + 0.5
    point[:along_x, 0] += frac[:along_x]
    point[along_x:, 1] += frac[along_x:]
    return point
