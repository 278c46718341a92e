"""Plan files written by the ground station: each child process's slice of the resolved scenario.

:mod:`gcs.plan.files` writes them for a run (``<out>/plan/``); ``python -m gcs.plan SCENARIO --out DIR`` writes
them for deployment, e.g. an agent plan to copy onto each drone's companion computer.
"""
