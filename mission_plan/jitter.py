"""Seeded jitter of launch pads and agent start times: what makes two seeds of one scenario two different runs.

Real launches never put a drone exactly on its mark, nor start every agent in the same instant. Pads move by up
to ``fleet.pad_jitter_m`` (uniform over the disc of that radius, so two pads ``s`` apart stay at least
``s - 2 pad_jitter_m`` apart), start times by up to ``fleet.start_jitter_s`` after the flood clock starts; both are drawn from the mission seed on their own streams, so they are the same in both engines.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mission_plan.fleet import VehicleSpec

PAD_STREAM = 0x9AD
START_STREAM = 0x57A
"""Salts of the two random streams, so they never repeat another consumer of the mission seed."""


def jittered_pads(vehicles: tuple[VehicleSpec, ...], jitter_m: float, seed: int) -> tuple[VehicleSpec, ...]:
    """Each pad moved by a uniform draw over the disc of radius ``jitter_m`` [m] (unchanged when it is 0)."""
    if jitter_m == 0.0:
        return vehicles
    rng = np.random.default_rng([PAD_STREAM, seed])
    radius = jitter_m * np.sqrt(rng.uniform(0.0, 1.0, len(vehicles)))
    bearing = rng.uniform(0.0, 2.0 * np.pi, len(vehicles))
    offsets = np.column_stack((radius * np.cos(bearing), radius * np.sin(bearing)))
    return tuple(
        replace(v, pad_enu_m=(v.pad_enu_m[0] + float(d[0]), v.pad_enu_m[1] + float(d[1]), v.pad_enu_m[2]))
        for v, d in zip(vehicles, offsets)
    )


def start_delays_s(vehicle_ids: tuple[int, ...], jitter_s: float, seed: int) -> tuple[float, ...]:
    """Each agent's start after the flood clock [s]: uniform in [0, jitter_s], by vehicle id."""
    if jitter_s == 0.0:
        return tuple(0.0 for _ in vehicle_ids)
    rng = np.random.default_rng([START_STREAM, seed])
    draws = rng.uniform(0.0, jitter_s, max(vehicle_ids, default=0) + 1)
    return tuple(float(draws[i]) for i in vehicle_ids)
