"""The drones' relative-position sensor, simulated from the truth (pure; both engines call it).

The paper's drones without GPS "can only sense their neighbours within limited distances" (§I) and know "the
relative positions of their neighbours" (§III-B). This is that sensor: every vehicle in ``ranging_range_m`` of the
observer, as (forward, right) [m] in the observer's TRUE horizontal body frame, plus white noise of
``ranging_sigma_m`` per axis. The observer turns it into the mission frame with its own heading ESTIMATE, so the
heading error of ``[sensors]`` rotates every measurement as it would on a real drone. The noise of one observer at
one time is drawn from (mission seed, observer, time): the same run twice gives the same measurements, in either
engine.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from comms.frames import en_to_body_fr
from comms.messages import NeighbourRanging
from mission_plan.weather import SensorSpec

_RANGING_STREAM = 0x52A9
"""Tag of the ranging noise stream among the seeded draws of one (seed, vehicle, time)."""


def observer_rng(seed: int, vehicle_id: int, t_s: float) -> np.random.Generator:
    """The generator of one observer's measurement at mission time ``t_s``."""
    t_ms = int(round(t_s * 1000.0))
    return np.random.default_rng([int(seed) & 0xFFFFFFFF, int(vehicle_id) & 0xFFFFFFFF, t_ms & 0xFFFFFFFF,
                                  _RANGING_STREAM])


def neighbour_ranging(
    t_s: float,
    observer: int,
    vehicle_ids: Sequence[int],
    positions_en_m: NDArray[np.float64],
    yaw_ned_rad: NDArray[np.float64],
    spec: SensorSpec,
    seed: int,
) -> NeighbourRanging:
    """What vehicle row ``observer`` measures at ``t_s``: every other live vehicle (a finite row of the true
    ``positions_en_m`` (N, 2)) within ``spec.ranging_range_m``, in its body frame from its true ``yaw_ned_rad``."""
    offsets = np.asarray(positions_en_m, dtype=float) - positions_en_m[observer]
    with np.errstate(invalid="ignore"):
        in_range = np.hypot(offsets[:, 0], offsets[:, 1]) <= spec.ranging_range_m
    in_range[observer] = False
    rows = np.flatnonzero(in_range)
    body = en_to_body_fr(offsets[rows], float(yaw_ned_rad[observer]))
    if spec.ranging_sigma_m > 0.0 and len(rows):
        body = body + spec.ranging_sigma_m * observer_rng(seed, vehicle_ids[observer], t_s).standard_normal(body.shape)
    return NeighbourRanging(
        vehicle_id=int(vehicle_ids[observer]), t_s=float(t_s),
        neighbour_ids=[int(vehicle_ids[r]) for r in rows],
        forward_right_m=[(float(f), float(r)) for f, r in body],
    )
