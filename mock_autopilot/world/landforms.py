"""Seeded landforms for the hydrodynamic flood: farmland with hedges and ditches, a meandering river valley, a basin
with depressions. Pure: parameters and a seed in, a :class:`Heightmap` out (heights in metres, 0 at the centre).

Each landform is a smooth trend (a slope, a valley, a bowl) plus fractal relief from ``fractal.fractal_noise`` and
its own features, so the water has somewhere to go that is not a circle: hedges deflect a breach fan and ditches
carry it; a meandering channel overtops on its outer bends first; depressions fill as separate ponds and merge
over their saddles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import numpy as np
from numpy.typing import NDArray

from mock_autopilot.world.fractal import fractal_noise
from mock_autopilot.world.heightmap import Heightmap


class Landform(Enum):
    """Which terrain the flood runs over."""

    FARMLAND = "farmland"
    VALLEY = "valley"
    BASIN = "basin"


@dataclass(frozen=True)
class LandformSpec:
    """Sizes of a landform [m]; the fields a landform does not use are ignored."""

    landform: Landform
    size_m: float = 120.0
    cell_m: float = 0.5
    relief_m: float = 0.3
    """Standard deviation of the fractal relief [m]."""
    slope: float = 0.005
    """Fall of the ground per metre along ``slope_toward_deg`` (farmland, and the valley's fall downstream)."""
    slope_toward_deg: float = 0.0
    """Direction the ground falls toward, counter-clockwise from east (the river flows this way)."""
    hedges: int = 4
    hedge_height_m: float = 0.6
    ditches: int = 2
    ditch_depth_m: float = 0.5
    channel_width_m: float = 8.0
    channel_depth_m: float = 1.2
    meander_amplitude_m: float = 14.0
    meander_wavelength_m: float = 70.0
    depressions: int = 5
    depression_depth_m: float = 0.8
    depression_radius_m: float = 12.0


def _grid_en_m(n: int, cell_m: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """East and north [m] of the cell centres of an n x n grid centred on the origin, row 0 north."""
    half = n * cell_m / 2.0
    axis = -half + (np.arange(n) + 0.5) * cell_m
    return np.meshgrid(axis, -axis)


def _along_across(east: NDArray[np.float64], north: NDArray[np.float64], toward_deg: float
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Coordinates along the fall direction and across it (to its left) [m]."""
    a = math.radians(toward_deg)
    return east * math.cos(a) + north * math.sin(a), -east * math.sin(a) + north * math.cos(a)


def _band(distance_m: NDArray[np.float64], half_width_m: float) -> NDArray[np.float64]:
    """A smooth 0..1 profile: 1 on a line, falling to 0 at ``half_width_m`` (cosine shoulder)."""
    x = np.clip(np.abs(distance_m) / half_width_m, 0.0, 1.0)
    return 0.5 * (1.0 + np.cos(math.pi * x))


def _farmland(spec: LandformSpec, east: NDArray[np.float64], north: NDArray[np.float64],
              rng: np.random.Generator) -> NDArray[np.float64]:
    """A plane falling along the slope with hedges (berms with gaps) and ditches at seeded places and angles."""
    along, across = _along_across(east, north, spec.slope_toward_deg)
    z = -spec.slope * along
    half = spec.size_m / 2.0
    for kind, count in (("hedge", spec.hedges), ("ditch", spec.ditches)):
        for _ in range(count):
            offset = rng.uniform(-0.35, 0.65) * half
            tilt = math.radians(rng.uniform(-35.0, 35.0))
            if kind == "hedge":
                d = (along - offset) * math.cos(tilt) - across * math.sin(tilt)
                gap_at = rng.uniform(-0.6, 0.6) * half
                gap = _band((across * math.cos(tilt) + along * math.sin(tilt)) - gap_at, rng.uniform(3.0, 6.0))
                z += spec.hedge_height_m * _band(d, 1.5) * (1.0 - gap)
            else:
                d = (across - offset) * math.cos(tilt) - along * math.sin(tilt)
                z -= spec.ditch_depth_m * _band(d, 1.5)
    return z


def _valley(spec: LandformSpec, east: NDArray[np.float64], north: NDArray[np.float64],
            rng: np.random.Generator) -> NDArray[np.float64]:
    """A floodplain falling downstream, rising gently to both sides, cut by a meandering channel that enters at the
    middle of the upstream edge (so an inlet there is in the channel whatever the seed)."""
    along, across = _along_across(east, north, spec.slope_toward_deg)
    wavelength = spec.meander_wavelength_m * rng.uniform(0.85, 1.15)
    upstream = along + spec.size_m / 2.0
    centre = spec.meander_amplitude_m * np.sin(2.0 * math.pi * upstream / wavelength)
    offset = across - centre
    plain = -spec.slope * along + 0.02 * np.abs(across) + 0.0004 * across ** 2
    return plain - spec.channel_depth_m * _band(offset, spec.channel_width_m)


def _basin(spec: LandformSpec, east: NDArray[np.float64], north: NDArray[np.float64],
           rng: np.random.Generator) -> NDArray[np.float64]:
    """A shallow bowl with seeded depressions (Gaussian hollows) that fill as ponds and merge over saddles."""
    half = spec.size_m / 2.0
    r = np.hypot(east, north)
    z = 0.4 * (r / half) ** 2
    for _ in range(spec.depressions):
        angle = rng.uniform(0.0, 2.0 * math.pi)
        dist = rng.uniform(0.15, 0.55) * half
        ce, cn = dist * math.cos(angle), dist * math.sin(angle)
        radius = spec.depression_radius_m * rng.uniform(0.7, 1.3)
        depth = spec.depression_depth_m * rng.uniform(0.6, 1.2)
        z -= depth * np.exp(-((east - ce) ** 2 + (north - cn) ** 2) / (2.0 * radius ** 2))
    return z


_SHAPES = {Landform.FARMLAND: _farmland, Landform.VALLEY: _valley, Landform.BASIN: _basin}


def landform_heightmap(spec: LandformSpec, seed: int) -> Heightmap:
    """The landform's heights on a north-up grid centred on the mission origin, height 0 at the origin."""
    n = max(int(round(spec.size_m / spec.cell_m)), 8)
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, 0x4D0D, list(Landform).index(spec.landform)])
    east, north = _grid_en_m(n, spec.cell_m)
    z = _SHAPES[spec.landform](spec, east, north, rng) + spec.relief_m * fractal_noise(n, 2.2, rng)
    if spec.landform is not Landform.VALLEY:
        z -= z[n // 2, n // 2]
    return Heightmap(z.astype(np.float32), spec.cell_m, (0.0, 0.0))
