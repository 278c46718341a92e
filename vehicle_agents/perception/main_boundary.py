"""Which of a frame's boundary points are the shore: the longest boundary, not the small ones beside it.

A flood is larger than the camera's footprint, so its shore crosses the frame as one long boundary between water
and land. The other boundaries a water mask holds are short and closed or cut off by the frame's border: a patch of
shadowed soil read as water, a piece of debris or a glint read as land, a dark vignetted corner. Eq 5's tracking
takes the median across the normal of the edge points in the middle of the image and the ground station cages the
flood with the points the drones report, so a few dozen points of a blob metres from the shore move both: the
principal axis of the points turns, the middle band of the turned axis reaches the blob, and one frame puts the
edge metres away.

The boundary points are grouped into chains: two points belong to the same chain when their pixels lie within
``LINK_PX`` of each other (each point marks a pixel beside its transition, and the marks of one boundary are
8-neighbours however it runs through the pixel grid; the margin joins a boundary broken by a pixel or two). The
longest chain is the shore. Another chain is kept only when it too runs into the frame's border and holds at least
``MIN_KEPT_FRACTION`` of the longest one's points: a shore that leaves the frame and comes back (a bay, a frame
across a bend) keeps both of its pieces, while a closed boundary inside the frame, however long, is a patch and not
the edge of a flood larger than the footprint.

Pure: image points in, which of them to keep out.
"""

from __future__ import annotations

import cv2
import numpy as np
from numpy.typing import NDArray

LINK_PX = 3
"""Points whose pixels lie within this many pixels (Chebyshev) of each other belong to the same boundary: the marks
are dilated by a ``LINK_PX``-wide square (odd) and labelled with 8-connectivity."""
MIN_KEPT_FRACTION = 0.5
"""A boundary into the frame's border with at least this share of the longest one's points is kept as a second
piece of the shore."""
_LINK = cv2.getStructuringElement(cv2.MORPH_RECT, (LINK_PX, LINK_PX))


def main_boundary_kept(points_px: NDArray[np.float64], shape: tuple[int, int]) -> NDArray[np.bool_] | None:
    """Which of the points (K, 2) [px; x, y] lie on the frame's shore (see the module): a (K,) mask, or None when
    the points form one boundary and all are kept.

    ``shape`` is the frame's (H, W).
    """
    if points_px.shape[0] < 3:
        return None
    height, width = shape
    pixels = points_px.astype(np.int32)  # the points lie between pixel centres, inside the frame
    columns, rows = pixels[:, 0], pixels[:, 1]
    marks = np.zeros((height, width), np.uint8)
    marks[rows, columns] = 1
    count, labels = cv2.connectedComponents(cv2.dilate(marks, _LINK), connectivity=8, ltype=cv2.CV_16U)
    if count <= 2:
        return None
    label_of = labels[rows, columns]
    sizes = np.bincount(label_of, minlength=count)
    at_border = (columns < LINK_PX) | (rows < LINK_PX) | (columns >= width - LINK_PX) | (rows >= height - LINK_PX)
    reaches_border = np.bincount(label_of[at_border], minlength=count) > 0
    kept = reaches_border & (sizes >= MIN_KEPT_FRACTION * sizes.max())
    kept[int(sizes.argmax())] = True
    if kept[1:].all():  # label 0 is the unmarked background
        return None
    return kept[label_of]
