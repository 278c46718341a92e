"""A drone without GPS corrects its drifting odometry with what it senses of its neighbours (pure).

The paper keeps GPS off most drones: they fly on odometry and "know the relative positions of their neighbours"
(§III-B). Odometry drifts with the distance flown (a visual or flow odometry's error is a fraction of the path), and
every drone drifts its own way, so the ring's shape and the edge points it reports spread apart. What a drone can
measure is the offset to each neighbour in range (:class:`comms.messages.NeighbourRanging`), and what it hears is
where each neighbour believes it is (its state message). Together they give one reading of its own error per
neighbour: ``c_i ≈ odometry_i − (p̂_j − z_ij)``, as good as the neighbour's belief.

Each drone solves, for itself, its row of the swarm's least squares: its drift is zero at its pad and grows at most
``odometry_drift_frac`` × distance flown (the prior, σ₀ = k·d), and each reading above is one observation of
σ = hypot(ranging σ, the neighbour's motion since its message). One Jacobi sweep of that system per new measurement,
low-passed over ``_SMOOTHING_TIME_S``, moves the swarm towards the joint solution: the drifts relative to one another
vanish within seconds, and what stays common to all is about their mean (the prior, weak against the readings,
pulls that common part towards the drones that flew least only over minutes). The GPS
leader is not used as a reference: its fix's error (σ 0.6 m in ``moderate``) would enter every drone's reading at
once, one measurement counted as many, while the pads know the common part better on a mission of minutes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from comms.frames import body_fr_to_en
from comms.messages import FLAG_HAS_GPS, FLAG_LEAVING, HeardState, NeighbourRanging

_PRIOR_FLOOR_M = 0.02
"""σ of the drift prior at the pad [m]: the pad is surveyed, not perfect."""
_NEIGHBOUR_MOTION_SIGMA_M = 0.1
"""What a neighbour's belief, predicted from its message to the measurement time, adds to a reading's σ [m]."""
_MAX_MESSAGE_AGE_S = 0.5
"""A neighbour heard longer ago than this (relayed copies, a lossy link) gives no reading."""
_SMOOTHING_TIME_S = 2.0
"""Time constant of the low-pass over the sweeps [s]: the drift grows by centimetres a second, the noise is white."""


def corrects_odometry(cooperative_position: bool, odometry_drift_frac: float, has_gps: bool) -> bool:
    """Does this drone run the correction (and read a relative-position sensor)? Only on odometry that drifts."""
    return cooperative_position and odometry_drift_frac > 0.0 and not has_gps


@dataclass(frozen=True)
class PositionCorrection:
    """One drone's odometry error estimate [m; E, N] (odometry minus the corrected position), the distance it has
    flown [m], its odometry at the last step and the time of the last ranging it used [s]."""

    correction_en_m: tuple[float, float] = (0.0, 0.0)
    flown_m: float = 0.0
    last_odometry_en_m: tuple[float, float] | None = None
    last_ranging_t_s: float = -math.inf

    def corrected(self, odometry_en_m: NDArray[np.float64]) -> NDArray[np.float64]:
        """The position the drone flies and reports: its odometry minus the estimated error."""
        return odometry_en_m - np.asarray(self.correction_en_m)


NO_CORRECTION = PositionCorrection()


def correction_step(
    state: PositionCorrection,
    odometry_en_m: NDArray[np.float64],
    velocity_en_mps: NDArray[np.float64],
    yaw_ned_rad: float,
    ranging: NeighbourRanging | None,
    heard: Mapping[int, HeardState],
    t_s: float,
    drift_frac: float,
    ranging_sigma_m: float,
) -> PositionCorrection:
    """The estimate after one control step at ``t_s`` (module doc); a ranging already used, none, or one with no
    usable neighbour only counts the distance flown (the estimate holds: the drift it found has not gone away)."""
    odometry = (float(odometry_en_m[0]), float(odometry_en_m[1]))
    flown_m = state.flown_m
    if state.last_odometry_en_m is not None:
        flown_m += math.hypot(odometry[0] - state.last_odometry_en_m[0], odometry[1] - state.last_odometry_en_m[1])
    if ranging is None or ranging.t_s <= state.last_ranging_t_s or not ranging.neighbour_ids:
        return PositionCorrection(state.correction_en_m, flown_m, odometry, state.last_ranging_t_s)
    readings = _readings(odometry_en_m - velocity_en_mps * (t_s - ranging.t_s), yaw_ned_rad, ranging, heard)
    if not len(readings):
        return PositionCorrection(state.correction_en_m, flown_m, odometry, state.last_ranging_t_s)
    weight_prior = 1.0 / (drift_frac * flown_m + _PRIOR_FLOOR_M) ** 2
    weight_reading = 1.0 / (ranging_sigma_m ** 2 + _NEIGHBOUR_MOTION_SIGMA_M ** 2)
    target = weight_reading * readings.sum(axis=0) / (weight_prior + weight_reading * len(readings))
    dt_s = ranging.t_s - state.last_ranging_t_s if math.isfinite(state.last_ranging_t_s) else 0.0
    gain = min(1.0, dt_s / _SMOOTHING_TIME_S)
    previous = np.asarray(state.correction_en_m)
    correction = previous + gain * (target - previous)
    return PositionCorrection((float(correction[0]), float(correction[1])), flown_m, odometry, ranging.t_s)


def _readings(odometry_at_ranging_en_m: NDArray[np.float64], yaw_ned_rad: float, ranging: NeighbourRanging,
              heard: Mapping[int, HeardState]) -> NDArray[np.float64]:
    """(K, 2) readings of the drone's own odometry error, one per ranged neighbour that flies on odometry too and
    was heard recently enough."""
    offsets_en_m = body_fr_to_en(np.asarray(ranging.forward_right_m, dtype=float).reshape(-1, 2), yaw_ned_rad)
    used, positions, velocities, ages = [], [], [], []
    for row, neighbour_id in enumerate(ranging.neighbour_ids):
        msg = heard.get(neighbour_id)
        if msg is None or msg.has(FLAG_HAS_GPS) or msg.has(FLAG_LEAVING):
            continue
        age_s = ranging.t_s - msg.t_s
        if abs(age_s) <= _MAX_MESSAGE_AGE_S:
            used.append(row)
            positions.append(msg.position_en_m)
            velocities.append(msg.velocity_en_mps)
            ages.append(age_s)
    if not used:
        return np.zeros((0, 2))
    believed_en_m = np.asarray(positions, dtype=float) + np.asarray(velocities, dtype=float) * np.asarray(ages)[:, None]
    return odometry_at_ranging_en_m - (believed_en_m - offsets_en_m[used])
