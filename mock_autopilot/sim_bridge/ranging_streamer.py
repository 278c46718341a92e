"""Publishes the relative-position sensors' measurements from the published truth (the camera process runs it).

Each drone gets, on ``ranging/<id>`` at ``[sensors] ranging_rate_hz`` of mission time, what its sensor measures of
the vehicles in range (:func:`mock_autopilot.relative_ranging.neighbour_ranging`), as the lockstep engine gives it
to the same onboard core. Only while position estimates err (``SensorSpec.ranging_used``): otherwise no drone reads
it; the drones that do subscribe (:func:`vehicle_agents.core.sensed_neighbours.reads_ranging`).
"""

from __future__ import annotations

from collections.abc import Collection, Sequence

import numpy as np

from comms.keys import MissionKeys
from comms.messages import encode
from comms.zenoh_session import ZenohSession
from mission_plan.weather import SensorSpec
from mock_autopilot.periodic_schedule import next_slot_s, slot_reached
from mock_autopilot.relative_ranging import neighbour_ranging
from mock_autopilot.sim_bridge.bridge import VehicleTruth


class RangingStreamer:
    """The measurements of ``carrier_ids`` (every drone of the plan), on the grid of the ranging rate."""

    def __init__(self, session: ZenohSession, mission: str, spec: SensorSpec, seed: int,
                 carrier_ids: Collection[int]) -> None:
        self.session = session
        self.keys = MissionKeys(mission)
        self.spec = spec
        self.seed = seed
        self.carrier_ids = frozenset(carrier_ids) if spec.ranging_used else frozenset()
        self._next_t_s = 0.0
        self.sent = 0

    def stream(self, now_s: float, vehicles: Sequence[VehicleTruth]) -> None:
        """Publish every living carrier's measurement if one is due at mission time ``now_s``."""
        if not self.carrier_ids or not slot_reached(self._next_t_s, now_s):
            return
        self._next_t_s = next_slot_s(self._next_t_s, 1.0 / self.spec.ranging_rate_hz, now_s)
        ids = [v.vehicle_id for v in vehicles]
        positions_en_m = np.array([v.position_enu_m[:2] if v.alive else (np.nan, np.nan) for v in vehicles],
                                  dtype=float).reshape(-1, 2)
        yaws = np.array([v.yaw_ned_rad for v in vehicles], dtype=float)
        for row, vehicle in enumerate(vehicles):
            if vehicle.alive and vehicle.vehicle_id in self.carrier_ids:
                msg = neighbour_ranging(now_s, row, ids, positions_en_m, yaws, self.spec, self.seed)
                self.session.put(self.keys.ranging(vehicle.vehicle_id), encode(msg))
                self.sent += 1
