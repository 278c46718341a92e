"""Small patches classified as land that lie wholly inside the water are water (floating debris).

Branches, litter and foam float on a flood: every cue of :mod:`vehicle_agents.perception.water_mask` reads them as
land, being darker, browner, whiter or rougher than the water round them. In a frame that is mostly water the few
land pixels at its border are what places eq 5's land centroid, so a handful of debris specks in the middle of the
water pulls that centroid, and the midpoint with it, into the flood, and adds their outlines to the edge points.
A land patch enclosed by water and smaller than ``MAX_HOLE_AREA_M2`` on the ground is not ground the swarm cages:
it is taken as water. A patch touching the image border may be the shore seen through the frame's edge and is
kept, as is any patch of real size (an island).
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import NDArray

MAX_HOLE_AREA_M2 = 0.5
"""Largest enclosed land patch taken as water [m² on the ground]: floating pieces are 0.15-0.6 m long."""


def fill_small_land_holes(mask: NDArray[np.bool_], ground_sample_m: float) -> NDArray[np.bool_]:
    """``mask`` (True = water) with each 4-connected land patch that touches no image border and covers at most
    ``MAX_HOLE_AREA_M2`` (at ``ground_sample_m`` metres per pixel) turned to water; the same array when none does.

    Land patches are 4-connected because a water class whose pixels meet only at a corner still encloses them
    (the 8-connected water round a hole).
    """
    max_hole_px = MAX_HOLE_AREA_M2 / (ground_sample_m * ground_sample_m)
    if not max_hole_px >= 1.0:
        return mask
    land = cv2.bitwise_not(mask.view(np.uint8)) & 1
    count, labels, stats, _ = cv2.connectedComponentsWithStats(land, connectivity=4, ltype=cv2.CV_32S)
    if count <= 1:
        return mask  # no land
    h, w = mask.shape
    left, top = stats[1:, cv2.CC_STAT_LEFT], stats[1:, cv2.CC_STAT_TOP]
    right = left + stats[1:, cv2.CC_STAT_WIDTH]
    bottom = top + stats[1:, cv2.CC_STAT_HEIGHT]
    hole = (left > 0) & (top > 0) & (right < w) & (bottom < h) & (stats[1:, cv2.CC_STAT_AREA] <= max_hole_px)
    if not hole.any():
        return mask
    fill = np.concatenate(([False], hole))
    return mask | fill[labels]
