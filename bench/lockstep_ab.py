"""One lockstep run of a scenario, for timing whole processes against another checkout (farm-bench --vs).

    farm-bench -n 5 -- .venv/bin/python bench/lockstep_ab.py circle improved \\
        --vs "sh -c 'cd /path/to/other/checkout && exec /path/to/.venv/bin/python bench/lockstep_ab.py circle improved'"

Imports come from the current directory's checkout (``sys.path[0]``), so the same venv times either tree. Prints the
run's own wall and CPU seconds (the engine loop only, without start-up and imports).
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path.cwd()))

from gcs.lockstep.engine import run_lockstep  # noqa: E402
from gcs.scenario import load_scenario  # noqa: E402


def main() -> None:
    scenario = load_scenario(sys.argv[1] if len(sys.argv) > 1 else "circle")
    mode = sys.argv[2] if len(sys.argv) > 2 else "improved"
    result = run_lockstep(scenario, mode)
    print(f"{scenario.name} {mode}: loop {result.wall_s:.2f} s wall, {result.cpu_s:.2f} s CPU, {result.steps} steps")


if __name__ == "__main__":
    main()
