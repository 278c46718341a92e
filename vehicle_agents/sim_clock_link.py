"""The agent's side of a simulation's clock over Zenoh: the clock ticks it computes on, the acknowledgements it sends.

Under a paced simulation clock (``--clock paced``) the agent does not keep time itself: it computes one control
tick for each :class:`~comms.messages.SimClockTick` (the mission time at which the fleet stands still, with every
input for that instant delivered) and acknowledges it once its setpoint and state message are out, so the fleet
may move on (:mod:`mock_autopilot.pacing`). With a free clock it still acknowledges each tick it computed, which
lets the simulator measure every agent's achieved control rate. On a real drone there is no simulator clock: the
agent runs with ``--clock free`` and nobody listens to its acknowledgements.
"""

from __future__ import annotations

from comms.keys import MissionKeys
from comms.messages import PaceAck, SimClockTick, decode, encode
from comms.zenoh_session import ZenohSession


class SimClockLink:
    """Clock ticks in, acknowledgements out, on an open Zenoh session (the agent's swarm session)."""

    def __init__(self, session: ZenohSession, keys: MissionKeys, vehicle_id: int) -> None:
        self.session = session
        self._ack_key = keys.pace(vehicle_id)
        self._participant = str(vehicle_id)
        self._ticks = session.subscribe(keys.clock)
        self._newest: SimClockTick | None = None

    def newest_tick(self) -> SimClockTick | None:
        """The newest clock tick heard so far (None before the first)."""
        for item in self._ticks.drain():
            tick = decode(SimClockTick, item.payload)
            if tick is not None and (self._newest is None or tick.t_s > self._newest.t_s):
                self._newest = tick
        return self._newest

    async def tick_after(self, t_s: float, timeout_s: float) -> SimClockTick | None:
        """The newest clock tick later than ``t_s``, waiting at most ``timeout_s`` wall seconds for one."""
        tick = self.newest_tick()
        if tick is not None and tick.t_s > t_s:
            return tick
        await self._ticks.wait_async(timeout_s)
        tick = self.newest_tick()
        return tick if tick is not None and tick.t_s > t_s else None

    def acknowledge(self, t_s: float, *, leaving: bool = False) -> None:
        """Tell the simulator this agent has done its part for mission time ``t_s`` (or is leaving)."""
        self.session.put(self._ack_key, encode(PaceAck(participant=self._participant, t_s=t_s, leaving=leaving)))
