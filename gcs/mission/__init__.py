"""``python -m gcs.mission``: run a scenario with the process-based system or the lockstep engine."""
