"""The mission plan: the scenario schema as frozen values, and the plan files each process of a mission reads.

A leaf package: it imports only the standard library, numpy and msgspec, never ``gcs``, ``vehicle_agents``,
``mock_autopilot`` or ``comms`` (tests/test_import_rules.py checks it). Everything that needs the flood model
(``launch_en_m = "auto"``) is resolved by the ground station (``gcs.scenario``), which then writes each child's
slice as a plan file (:mod:`mission_plan.plans`, :mod:`mission_plan.plan_files`). A drone's companion computer
therefore depends on this package and nothing of the ground station.
"""
