"""Where the collision barrier sees the neighbours: through the drone's relative-position sensor (pure).

The laws place neighbours where their state messages say they are, in the frame of each sender's own estimate, and
place this drone where its own estimate says. Under estimator errors the two frames disagree: a GPS fix's bias
(σ 0.5 m per axis in ``moderate``) or a drift not yet corrected moves one drone's whole picture, and two drones
launched 1.4 m apart can each believe the other 2.3 m away, where the barrier's 2.5 m minimum barely acts. What the
drone measures of a neighbour in range (:class:`comms.messages.NeighbourRanging`, σ 0.1 m, turned into the mission
frame with its own heading) carries none of that, so the barrier (:func:`vehicle_agents.control.safety
.collision_barrier`) keeps clear of the neighbour at this drone's position plus the measured offset. The laws keep
the broadcast positions: they steer on the shared picture; only keeping clear uses the sensor.

Every drone of improved mode reads the sensor for this while the estimates err (``ControlParams.ranging_available``);
a drone without GPS also corrects its odometry with it (:mod:`vehicle_agents.core.cooperative_position`).
"""

from __future__ import annotations

import numpy as np

from comms.frames import body_fr_to_en
from comms.messages import NeighbourRanging
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.types import SensedOffsets
from vehicle_agents.core.cooperative_position import corrects_odometry

MAX_RANGING_AGE_S = 0.5
"""A measurement older than this is not where the neighbour is any more [s] (the sensor runs at 10 Hz)."""


def reads_ranging(params: ControlParams, has_gps: bool) -> bool:
    """Does this drone read its relative-position sensor: to correct drifting odometry, or for its barrier?"""
    if not params.ranging_available:
        return False
    return params.sensed_barrier or corrects_odometry(params.cooperative_position, params.odometry_drift_frac, has_gps)


def sensed_offsets(ranging: NeighbourRanging | None, yaw_ned_rad: float, t_s: float) -> SensedOffsets | None:
    """Each ranged neighbour's offset from this drone [m; E, N], from a measurement at most ``MAX_RANGING_AGE_S``
    old, turned into the mission frame with the drone's heading estimate; None without one."""
    if ranging is None or not ranging.neighbour_ids or not 0.0 <= t_s - ranging.t_s <= MAX_RANGING_AGE_S:
        return None
    offsets = body_fr_to_en(np.asarray(ranging.forward_right_m, dtype=float).reshape(-1, 2), yaw_ned_rad)
    return SensedOffsets(tuple(ranging.neighbour_ids), offsets, t_s - ranging.t_s)
