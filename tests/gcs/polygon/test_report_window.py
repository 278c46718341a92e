"""The ground station fuses each boundary drone's reports of the last half second: one misread frame is outvoted."""

from __future__ import annotations

import math

import numpy as np

from comms.messages import NeighbourState
from gcs.metrics.polygon_quality import polygon_iou
from gcs.polygon.report_window import WINDOW_S, recent_points, remembered
from gcs.polygon.reports import aggregate_polygon

ORDER = list(range(1, 9))
RADIUS_M = 12.0
TRUTH = np.stack([RADIUS_M * np.cos(np.linspace(0, 2 * math.pi, 256, endpoint=False)),
                  RADIUS_M * np.sin(np.linspace(0, 2 * math.pi, 256, endpoint=False))], axis=1)


def boundary(vid: int, t_s: float, seen_radius_m: float = RADIUS_M) -> NeighbourState:
    """A boundary drone on the circle reporting an arc of edge at ``seen_radius_m`` around its bearing."""
    angle = 2 * math.pi * (vid - 1) / 8
    arc = np.linspace(angle - 0.4, angle + 0.4, 24)
    edge = [(seen_radius_m * math.cos(a), seen_radius_m * math.sin(a)) for a in arc]
    return NeighbourState(sender_id=vid, role="boundary", seq=int(t_s * 20), t_s=t_s,
                          position_en_m=(RADIUS_M * math.cos(angle), RADIUS_M * math.sin(angle)), altitude_m=10.0,
                          edge_points_en_m=edge)


def test_reports_are_kept_for_the_window_once_each() -> None:
    history = {}
    for k in range(30):
        t_s = 10.0 + 0.05 * k
        heard = {vid: boundary(vid, t_s) for vid in ORDER}
        history = remembered(history, heard, ORDER, t_s)
        history = remembered(history, heard, ORDER, t_s)  # the same messages again: not a second report
    assert all(len(history[vid]) == round(WINDOW_S / 0.05) + 1 for vid in ORDER)
    assert len(recent_points(history, 3, 10.0 + 0.05 * 29)) == 24 * len(history[3])
    assert recent_points(history, 3, 20.0).shape == (0, 2)
    assert remembered(history, {}, ORDER, 20.0) == {}


def test_one_misread_report_is_outvoted_by_the_drone_s_reports_before_it() -> None:
    """Drone 3's newest report puts the edge 6 m outside the flood (a cloud shadow's edge seen from a tilted drone):
    in its last two messages (one camera frame at half the control rate): from the newest messages alone the
    polygon bulges; fused over half a second it does not."""
    history = {}
    t_s = 10.0
    for k in range(10):
        t_s = 10.0 + 0.05 * k
        heard = {vid: boundary(vid, t_s, RADIUS_M + 6.0 if (vid == 3 and k >= 8) else RADIUS_M) for vid in ORDER}
        history = remembered(history, heard, ORDER, t_s)
    newest_only = aggregate_polygon(heard, ORDER, np.zeros(2), now_s=t_s, max_age_s=1.0)
    fused = aggregate_polygon(heard, ORDER, np.zeros(2), now_s=t_s, max_age_s=1.0, history=history)
    assert polygon_iou(newest_only, TRUTH) < 0.95
    assert polygon_iou(fused, TRUTH) > 0.98
