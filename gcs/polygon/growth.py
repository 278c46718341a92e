"""How fast the caged polygon grows: what a rescue centre reads as the flood's spreading rate (SPEC §6)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from gcs.mission_record import PolygonSample
from gcs.polygon.ring import ring_area_m2


def area_growth_rate_m2ps(t_s: ArrayLike, area_m2: ArrayLike, window_s: float = 5.0) -> float:
    """Least-squares slope [m²/s] of area over the last ``window_s`` seconds; NaN with fewer than two samples.

    A fitted slope rather than a last-two-samples difference, because the polygon jitters with perception noise.
    """
    t = np.asarray(t_s, dtype=float)
    a = np.asarray(area_m2, dtype=float)
    ok = np.isfinite(t) & np.isfinite(a)
    t, a = t[ok], a[ok]
    if len(t) < 2:
        return math.nan
    recent = t >= t.max() - window_s
    t, a = t[recent], a[recent]
    if len(t) < 2 or np.ptp(t) <= 0.0:
        return math.nan
    slope, _ = np.polyfit(t - t.mean(), a, 1)
    return float(slope)


def polygon_growth_rate_m2ps(samples: Sequence[PolygonSample], window_s: float = 5.0) -> float:
    """Area growth rate [m²/s] of a polygon time series over its last ``window_s`` seconds."""
    return area_growth_rate_m2ps([s.t_s for s in samples], [ring_area_m2(s.ring_en_m) for s in samples], window_s)


def equivalent_radius_m(area_m2: float) -> float:
    """Radius [m] of the circle with this area: a one-number size for a roughly round flood."""
    return math.sqrt(max(area_m2, 0.0) / math.pi)
