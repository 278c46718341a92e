"""What a mission run records, whichever engine ran it: the input of the metrics and of every report.

The lockstep engine and the process-based mission both fill one of these, so their metrics.json, polygons and plots
come from the same code. Arrays are in the mission ENU frame (metres, seconds on the flood clock).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class PolygonSample:
    """The ground station's caged polygon at one time: a (K, 2) counter-clockwise ring [m; east, north]."""

    t_s: float
    ring_en_m: NDArray[np.float64]


@dataclass
class MissionRecord:
    """Ground-truth time series of one run, sampled at a fixed period.

    ``positions_enu_m[k, i]`` is vehicle ``i``'s true position at ``t_s[k]``; ``footprint_side_m[k, i]`` its camera
    footprint side then (0 when it is not flying). ``alive[k, i]`` is False once the vehicle or its agent is lost.
    ``commands_enu_mps`` holds the velocity each vehicle's control law asked for (for the effort metric).
    """

    scenario: str
    mode: str
    engine: str
    seed: int
    vehicle_ids: list[int]
    roles: list[str]
    t_s: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    positions_enu_m: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 0, 3)))
    commands_enu_mps: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 0, 3)))
    footprint_side_m: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 0)))
    alive: NDArray[np.bool_] = field(default_factory=lambda: np.zeros((0, 0), dtype=bool))
    polygons: list[PolygonSample] = field(default_factory=list)
    encircle_time_s: float | None = None
    climb_events: list[int] = field(default_factory=list)
    events: list[tuple[float, str]] = field(default_factory=list)
    refused_copies: list[int | None] = field(default_factory=list)
    """Relayed copies each vehicle refused as impossible (``gcs.relay_refusals``); None where not reported."""
    ground_refused_copies: int | None = None
    """The same, refused by the ground station's radio node (None: the station is outside the radio)."""
