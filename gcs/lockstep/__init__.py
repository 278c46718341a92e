"""The lockstep engine: a whole mission in one process on one simulated clock (SPEC §2-§5).

The same onboard core as the per-process agents (:func:`vehicle_agents.core.onboard.onboard_step`, called for the
whole fleet), a vehicle backend (:mod:`mock_autopilot.backends`), the camera renderer and perception on the camera's
frame grid, and :class:`comms.radio_model.RadioModel` for range, loss and latency. Deterministic for a seed.
Entry points: :func:`gcs.lockstep.engine.run_lockstep` (pure run, returns the record) and
:func:`gcs.lockstep.run.run_mission` (the CLI's: run and write the outputs).
"""
