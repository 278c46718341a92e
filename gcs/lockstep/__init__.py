"""The lockstep engine: a whole mission in one process on one simulated clock (SPEC §2-§5).

Same control code as the per-process agents (:func:`vehicle_agents.control.step.control_step`), the mock
autopilot's kinematics, the camera renderer and perception at every control step, and the comms team's radio
model for range, loss and latency. Deterministic for a seed. Entry points: :func:`gcs.lockstep.engine.run_lockstep`
(pure run, returns the record) and :func:`gcs.lockstep.run.run_mission` (the CLI's: run and write the outputs).
"""
