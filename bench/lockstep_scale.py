"""Benchmark: the largest fleet the lockstep engine still runs at >= 1x real time (camera + perception of every
vehicle at every camera frame).

Fleets are the `circle` scenario scaled up: boundary drones per group b, followers in one layer sized like the
paper's (half the boundary count), the flood radius and radio range scaled with sqrt(N / 13) so that the area per
vehicle stays the paper's. Each size runs ``--sim`` seconds of improved mode (the first seconds include the
encircling, the busiest phase).

    .venv/bin/python -m bench.lockstep_scale [--sim 10] [--sizes 4 8 12 16 24] [--set control_rate_hz=10 ...]
"""

from __future__ import annotations

import argparse
import math

from gcs.lockstep.engine import run_lockstep
from gcs.scenario import load_scenario
from mission_plan.roles import Role


def scaled_overrides(per_group: int) -> list[str]:
    boundary = 2 * per_group
    followers = max(1, boundary // 2)
    n = boundary + 1 + followers
    s = math.sqrt(n / 13.0)
    return [
        f"fleet.boundary_per_group={per_group}",
        f"fleet.follower_layers=[{followers}]",
        f"flood.radius_start_m={12.0 * s:.2f}",
        f"flood.radius_end_m={16.0 * s:.2f}",
        f"fleet.launch_en_m=[{12.0 * s + 2.0:.2f}, 0.0]",
        f"radio.range_m={25.0 * s:.1f}",
    ]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--sim", type=float, default=10.0)
    parser.add_argument("--sizes", type=int, nargs="*", default=[4, 8, 12, 16, 24])
    parser.add_argument("--mode", default="improved")
    parser.add_argument("--cameras", choices=("all", Role.BOUNDARY.value), default="all",
                        help="whose camera is rendered and segmented at every frame (default: every vehicle's)")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                        help="scenario override applied after the scaling, e.g. control_rate_hz=10")
    ns = parser.parse_args()
    print("| vehicles | boundary | followers | sim [s] | wall [s] | x real time (wall) | CPU [s] | x real time (CPU) |")
    print("|---|---|---|---|---|---|---|---|")
    for per_group in ns.sizes:
        scenario = load_scenario("circle", scaled_overrides(per_group) + ns.overrides)
        result = run_lockstep(scenario, ns.mode, duration_s=ns.sim, cameras=ns.cameras)
        n = len(scenario.vehicles)
        print(f"| {n} | {2 * per_group} | {n - 2 * per_group - 1} | {ns.sim:g} | {result.wall_s:.2f} | "
              f"{ns.sim / result.wall_s:.2f} | {result.cpu_s:.2f} | {ns.sim / result.cpu_s:.2f} |", flush=True)


if __name__ == "__main__":
    main()
