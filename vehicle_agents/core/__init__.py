"""The onboard core: one pure step for N drones, called by an agent process (N = 1) and the lockstep engine (N = fleet).

Inputs are what the drones can know (their autopilots' telemetry, the perception result of each one's newest camera
frame, the decoded radio inbox, the ground station's order, the mission time); outputs are velocity setpoints, the
state messages to broadcast and the flight-phase actions, plus the new state. No sockets, clocks or files: the
agent's asyncio loop (:mod:`vehicle_agents.agent`) and the lockstep engine (:mod:`gcs.lockstep.engine`) are the
shells around it, so what a drone does is decided by the same code in both engines.
"""
