"""The ground under a drone: height above ground for the rangefinder and the camera (flat unless the flood has relief).

Drones hold their altitude above home (the mission ENU origin), so over relief the ground is nearer or farther than
that altitude says. A flood model with relief answers ``ground_height_m(points)``; heights are taken relative to the
ground at the origin, which is where ``up = 0`` is. Models without it are flat, and height above ground is ``up``.
"""

from __future__ import annotations

import weakref
from functools import lru_cache
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

_ORIGIN = np.zeros((1, 2))
_origin_ground: weakref.WeakKeyDictionary[Any, tuple[float, float]] = weakref.WeakKeyDictionary()


@runtime_checkable
class GroundRelief(Protocol):
    """A flood model over terrain: the ground height [m] at each (..., 2) east/north point."""

    def ground_height_m(self, points_en_m: ArrayLike) -> NDArray[np.float64]:
        ...


@lru_cache(maxsize=64)
def has_relief(model_type: type) -> bool:
    """Whether a flood model class answers ground heights (a Protocol check per class, not per call: it is slow)."""
    return issubclass(model_type, GroundRelief)


def _origin_heights_m(relief: Any) -> tuple[float, float]:
    """The ground at the origin as a batch of points reads it and as a single point reads it (a model may sample the
    two ways differently); asked once per model, as every frame and rangefinder reading needs it."""
    try:
        cached = _origin_ground.get(relief)
    except TypeError:
        cached = None
    if cached is None:
        cached = (float(relief.ground_height_m(_ORIGIN)[0]), float(relief.ground_height_m(_ORIGIN[0])))
        try:
            _origin_ground[relief] = cached
        except TypeError:
            pass
    return cached


def relative_ground_m(flood: object, points_en_m: ArrayLike) -> NDArray[np.float64]:
    """Ground height above the origin's ground [m] at each (..., 2) point; zeros for a flat world."""
    p = np.asarray(points_en_m, dtype=float)
    if not has_relief(type(flood)):
        return np.zeros(p.shape[:-1])
    relief: Any = flood
    return np.asarray(relief.ground_height_m(p), float) - _origin_heights_m(relief)[0]


def height_above_ground_m(flood: object, position_enu_m: ArrayLike) -> float:
    """What a downward rangefinder reads [m]: the drone's ``up`` minus the ground below it."""
    pos = np.asarray(position_enu_m, dtype=float).reshape(-1)
    if not has_relief(type(flood)):
        return float(pos[2])
    relief: Any = flood
    below = float(relief.ground_height_m(pos[:2]))
    return float(pos[2]) - (below - _origin_heights_m(relief)[1])
