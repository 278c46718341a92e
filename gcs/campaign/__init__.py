"""Campaigns: one scenario over seeds x modes x a grid of overrides, each run a lockstep mission on dask.distributed.

``grid`` (pure: arguments, run list, run ids), ``runner`` (one run in a worker, one flat row), ``store`` (rows as
Parquet files), ``summary`` (pure statistics and summary.md), ``plots`` (box plots), ``progress`` (the live view),
``cli`` (the shell), ``results_doc`` (docs/RESULTS.md from campaign rows).
"""
