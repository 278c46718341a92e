"""Which vehicles the ground station counts as lost, since when, and which losses end.

A vehicle is lost when its heartbeat stops on the GCS link or when its agent is gone (its liveliness token vanished,
or its process exited). The two differ in what comes after: an agent that is gone does not come back (the process
has nothing left to fly), while a silent link can return, as QGroundControl sees a vehicle reappear when its
heartbeat does. A host stalled for a second under 208 agents silences a dozen links at once and every one is back
within a fraction of a second; counted lost for the rest of the run, those vehicles would leave the caged polygon's
feed and score no coverage while they fly on. So a vehicle lost only to link silence counts
again once its heartbeat returns; the loss itself stays in the events log and in the record (its alive flag went
False, then True again). Pure bookkeeping: the shell (:mod:`gcs.processes.ground_station`) feeds it the events.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class LostVehicles:
    """The vehicles lost now, by id, each with the flood time [s] it was lost at."""

    since_flood_s: dict[int, float] = field(default_factory=dict)
    agents_gone: set[int] = field(default_factory=set)
    """Vehicles whose agent is gone: lost for good."""

    def link_silent(self, vehicle_id: int, flood_t_s: float) -> None:
        """The vehicle's heartbeat stopped on the GCS link."""
        self.since_flood_s.setdefault(vehicle_id, flood_t_s)

    def agent_gone(self, vehicle_id: int, flood_t_s: float) -> None:
        """The vehicle's agent is gone (liveliness token vanished or process exited)."""
        self.agents_gone.add(vehicle_id)
        self.since_flood_s.setdefault(vehicle_id, flood_t_s)

    def link_back(self, vehicle_id: int) -> bool:
        """The vehicle's heartbeat returned; True when that ends its loss (it was lost to link silence only)."""
        if vehicle_id in self.since_flood_s and vehicle_id not in self.agents_gone:
            del self.since_flood_s[vehicle_id]
            return True
        return False
