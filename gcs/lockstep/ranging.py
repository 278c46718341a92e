"""The fleet's relative-position sensors in the lockstep engine: who carries one, when the next measurement is due
(``[sensors] ranging_rate_hz``), and each drone's newest measurement, which it keeps between measurements."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from comms.messages import NeighbourRanging
from mission_plan.weather import SensorSpec
from mock_autopilot.periodic_schedule import next_slot_s, slot_reached
from mock_autopilot.relative_ranging import neighbour_ranging
from vehicle_agents.control.params import ControlParams
from vehicle_agents.core.sensed_neighbours import reads_ranging


@dataclass
class LockstepRanging:
    """Measurements for the drones that read their sensors, on the grid of the ranging rate, from the true positions
    and yaws."""

    vehicle_ids: list[int]
    carriers: list[int]
    spec: SensorSpec
    seed: int
    latest: list[NeighbourRanging | None] = field(default_factory=list)
    next_t_s: float = 0.0

    @classmethod
    def of_fleet(cls, vehicle_ids: list[int], has_gps: NDArray[np.bool_], spec: SensorSpec, params: ControlParams,
                 seed: int) -> LockstepRanging:
        """Every drone that reads its sensor measures (:func:`vehicle_agents.core.sensed_neighbours.reads_ranging`)."""
        carriers = [i for i, gps in enumerate(has_gps) if spec.ranging_used and reads_ranging(params, bool(gps))]
        return cls(vehicle_ids, carriers, spec, seed, [None] * len(vehicle_ids))

    def measure(self, t_s: float, positions_enu_m: NDArray[np.float64], yaw_ned_rad: NDArray[np.float64],
                alive: NDArray[np.bool_]) -> None:
        """Every living carrier's measurement when one is due (``positions_enu_m``: NaN rows for the dead)."""
        if not self.carriers or not slot_reached(self.next_t_s, t_s):
            return
        self.next_t_s = next_slot_s(self.next_t_s, 1.0 / self.spec.ranging_rate_hz, t_s)
        positions_en_m = positions_enu_m[:, :2]
        for i in (i for i in self.carriers if alive[i]):
            self.latest[i] = neighbour_ranging(t_s, i, self.vehicle_ids, positions_en_m, yaw_ned_rad, self.spec,
                                               self.seed)
