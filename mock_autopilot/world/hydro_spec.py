"""What a hydrodynamic flood run needs, as frozen values: the ground, friction, sources, rain, boundaries and times.

Times here are *hydraulic* seconds (the solver's clock); ``time_scale`` maps the flood clock onto them. A hydrograph
is a piecewise-linear discharge Q(t) [m³/s], held at its last value after its last time and zero before its first.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

import numpy as np


class SourceKind(Enum):
    """Where a source pours its water: over a disc around a point, or across a line (a breach, a river inlet)."""

    POINT = "point"
    LINE = "line"


class BoundaryKind(Enum):
    """What an edge of the domain does with water: reflect it (a wall) or let it leave (free outflow)."""

    REFLECTIVE = "reflective"
    OUTFLOW = "outflow"


SIDES: tuple[str, ...] = ("north", "south", "east", "west")


@dataclass(frozen=True)
class Hydrograph:
    """Discharge [m³/s] at hydraulic times [s], linear in between."""

    t_s: tuple[float, ...]
    q_m3ps: tuple[float, ...]

    def rate_m3ps(self, t_s: float) -> float:
        """Q(t) [m³/s]: zero before the first time, held after the last."""
        if t_s < self.t_s[0]:
            return 0.0
        return float(np.interp(t_s, self.t_s, self.q_m3ps))

    def volume_m3(self, t_end_s: float) -> float:
        """∫ Q dt from the first time to ``t_end_s`` [m³] (exact for the piecewise-linear hydrograph)."""
        times = np.asarray(self.t_s, float)
        if t_end_s <= times[0]:
            return 0.0
        inside = times[times < t_end_s]
        knots = np.append(inside, t_end_s)
        q = np.interp(knots, self.t_s, self.q_m3ps)
        return float(np.sum(0.5 * (q[1:] + q[:-1]) * np.diff(knots)))


@dataclass(frozen=True)
class Source:
    """Water entering the domain: at a point (over a disc of ``radius_m``) or along a line between two points."""

    kind: SourceKind
    points_en_m: tuple[tuple[float, float], ...]
    hydrograph: Hydrograph
    radius_m: float = 3.0

    @property
    def anchor_en_m(self) -> tuple[float, float]:
        """The point the caged flood component must hold: the point, or the middle of the line."""
        p = np.mean(np.asarray(self.points_en_m, float), axis=0)
        return float(p[0]), float(p[1])


@dataclass(frozen=True)
class HydroSpec:
    """One solver run: mesh, friction, water in, edges, and how long and how often to record depth."""

    mesh_cell_m: float
    manning_n: float
    sources: tuple[Source, ...]
    rain_mm_per_h: float
    rain_until_s: float
    boundaries: tuple[BoundaryKind, BoundaryKind, BoundaryKind, BoundaryKind]
    """One per side, in the order of :data:`SIDES`."""
    end_s: float
    frame_interval_s: float

    def volume_in_m3(self, t_end_s: float, domain_area_m2: float) -> float:
        """Water the sources and rain put in from t = 0 to ``t_end_s`` [m³]: the reference for conservation."""
        rain = self.rain_mm_per_h / 3.6e6 * domain_area_m2 * min(max(t_end_s, 0.0), self.rain_until_s)
        return rain + sum(s.hydrograph.volume_m3(t_end_s) for s in self.sources)
