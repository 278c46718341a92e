"""Small patches classified as land that lie wholly inside the water are water (floating debris).

Branches, litter and foam float on a flood: every cue of :mod:`vehicle_agents.perception.water_mask` reads them as
land, being darker, browner, whiter or rougher than the water round them. In a frame that is mostly water the few
land pixels at its border are what places eq 5's land centroid, so a handful of debris specks in the middle of the
water pulls that centroid, and the midpoint with it, into the flood, and adds their outlines to the edge points.
A land patch enclosed by water and smaller than ``MAX_HOLE_AREA_M2`` on the ground is not ground the swarm cages:
it is taken as water. A patch touching the image border may be the shore seen through the frame's edge and is
kept, as is any patch of real size (an island). The holes come from the water's outlines (about 15 µs a 128x128
frame; labelling the land's components costs ten times that with OpenCV on one thread, as agents run it).
:mod:`vehicle_agents.perception.water_mask` applies this to the blue cue's mask only: where the grey-water cue
decides, its water class can itself spill round real land, and filling what it encloses makes that worse.
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import NDArray

MAX_HOLE_AREA_M2 = 0.5
"""Largest enclosed land patch taken as water [m² on the ground]: floating pieces are 0.15-0.6 m long."""


def fill_small_land_holes(mask: NDArray[np.bool_], ground_sample_m: float) -> NDArray[np.bool_]:
    """``mask`` (True = water) with each land patch that water encloses, and whose outline encloses at most
    ``MAX_HOLE_AREA_M2`` (at ``ground_sample_m`` metres per pixel), turned to water; the same array when none is.

    The holes are the inner outlines of the water's 8-connected components (``cv2.findContours``, two levels): land
    through the image border is never enclosed, and two land pixels meeting only at a corner are two holes. An
    outline runs through the water pixels round its hole, so its area is the hole's plus about half its rim: small
    patches are measured a little large, which errs towards keeping land.
    """
    max_hole_px = MAX_HOLE_AREA_M2 / (ground_sample_m * ground_sample_m)
    if not max_hole_px >= 1.0:
        return mask
    contours, hierarchy = cv2.findContours(mask.view(np.uint8), cv2.RETR_CCOMP, cv2.CHAIN_APPROX_SIMPLE)
    if hierarchy is None:
        return mask  # no water
    holes = [outline for outline, (_, _, _, parent) in zip(contours, hierarchy[0])
             if parent >= 0 and cv2.contourArea(outline) <= max_hole_px]
    if not holes:
        return mask
    filled = mask.astype(np.uint8)
    cv2.drawContours(filled, holes, -1, 1, thickness=cv2.FILLED)
    return filled.view(bool)
