"""How the true flood itself behaved during a run: the caged part of the water and how fast its edge moved.

A flood with several wet components (ponds, a river's side pools) is scored against one of them, the caged
component (``FloodModel.boundary_en_m``); ``caged_area_fraction`` says how much of all the water that is. The edge
speed is the outward normal speed along the perimeter: for each vertex of the ring at ``t + dt``, its distance to
the ring at ``t``, over ``dt``; pooled over the run it gives the spread between a front that runs and one that stalls.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gcs.polygon.ring import densify_ring, distance_to_ring_m, open_ring
from mock_autopilot.world.flood_model import FloodModel

EDGE_SPEED_PERIOD_S = 5.0
"""Flood time between the two rings an edge speed is measured on [s]."""
EDGE_SAMPLE_SPACING_M = 0.5
"""The later ring is densified to this vertex spacing, so long straight stretches count by their length."""


def wet_area_m2(flood: FloodModel, t_s: float) -> float:
    """All the water's area [m²]: the model's total where it has several components, else its flooded area."""
    total = getattr(flood, "wet_area_m2", None)
    return float(total(t_s)) if callable(total) else float(flood.area_m2(t_s))


def edge_speeds_mps(flood: FloodModel, t_start_s: float, t_end_s: float,
                    period_s: float = EDGE_SPEED_PERIOD_S) -> np.ndarray:
    """Outward edge speed [m/s] at points along the perimeter, pooled over ``[t_start_s, t_end_s]``."""
    speeds = []
    times = np.arange(t_start_s, t_end_s - 1e-9, period_s)
    for t0 in times:
        t1 = min(t0 + period_s, t_end_s)
        before, after = open_ring(flood.boundary_en_m(float(t0))), open_ring(flood.boundary_en_m(float(t1)))
        if len(before) < 3 or len(after) < 3 or t1 <= t0:
            continue
        speeds.append(distance_to_ring_m(densify_ring(after, EDGE_SAMPLE_SPACING_M), before) / (t1 - t0))
    return np.concatenate(speeds) if speeds else np.zeros(0)


def flood_clock(flood: FloodModel) -> dict[str, float]:
    """How the flood's own clock ran against the mission's: ``flood_time_scale`` (hydraulic seconds per mission
    second) and ``flood_hydraulic_start_s`` (hydraulic time at mission flood time 0) for a hydrodynamic flood, whose
    hours-long run may be played faster than the solver's clock (a result's times and edge speeds are in mission
    time; these two turn them into hydraulic time); NaN for a flood drawn on the mission clock."""
    scale, start = getattr(flood, "time_scale", None), getattr(flood, "start_s", None)
    if not isinstance(scale, (int, float)) or not isinstance(start, (int, float)):
        return {"flood_time_scale": math.nan, "flood_hydraulic_start_s": math.nan}
    return {"flood_time_scale": float(scale), "flood_hydraulic_start_s": float(start)}


def flood_extent_summary(flood: FloodModel, t_start_s: float, t_end_s: float) -> dict[str, Any]:
    """``caged_area_final_m2``, ``wet_area_final_m2``, ``caged_area_fraction_final``, edge speed p50/p95/max and
    the flood's clock (:func:`flood_clock`)."""
    caged, total = float(flood.area_m2(t_end_s)), wet_area_m2(flood, t_end_s)
    speeds = edge_speeds_mps(flood, t_start_s, t_end_s)
    finite = speeds[np.isfinite(speeds)]

    def pct(q: float) -> float:
        return float(np.percentile(finite, q)) if len(finite) else math.nan

    return {
        "caged_area_final_m2": caged,
        "wet_area_final_m2": total,
        "caged_area_fraction_final": caged / total if total > 0 else math.nan,
        "edge_speed_p50_mps": pct(50),
        "edge_speed_p95_mps": pct(95),
        "edge_speed_max_mps": float(finite.max()) if len(finite) else math.nan,
        **flood_clock(flood),
    }
