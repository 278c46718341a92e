"""``python -m gcs.plan SCENARIO --out DIR [--set KEY=VALUE] [--mode M] [--seed S] [--mission NAME]``.

Resolves a scenario as the ground station does (defaults, overrides, seed, "auto" launch pads with the flood
model; the flood table is checked too) and writes its plan files to DIR: ``agent_<id>.json`` for each drone's
companion computer (``python -m vehicle_agents --plan``), ``fleet.json`` (``python -m mock_autopilot.sim_bridge
--plan``) and ``cameras.json`` (``python -m mock_autopilot.sim_bridge.cameras --plan``), and the mission key ``mission.key`` (mode 0600: new, or a
copy of ``--key-file``) that signs the ground station's commands and the drones' states; copy it with the plans
(``scp -p``). Bad input prints one line
and exits with 2.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from comms.key_file import KeyFileError
from comms.keys import KeyNameError, validate_mission
from gcs.one_line_argparse import EXIT_USAGE, OneLineArgumentParser
from gcs.plan.files import write_plans
from gcs.scenario import ScenarioError, check_flood, load_scenario
from mission_plan.control_params import MODES, ControlMode

def build_parser() -> argparse.ArgumentParser:
    p = OneLineArgumentParser(prog="python -m gcs.plan", description="Write a scenario's plan files for deployment.",
                              label="gcs.plan")
    p.add_argument("scenario", help="bundled scenario name (circle, ellipse, ...) or path to a .toml file")
    p.add_argument("--out", type=Path, required=True, metavar="DIR", help="folder for the plan files")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                   help="override a scenario parameter (repeatable)")
    p.add_argument("--mode", choices=MODES, default=ControlMode.IMPROVED.value, help="control laws (default improved)")
    p.add_argument("--seed", type=int, default=None, help="mission seed (default: the scenario's)")
    p.add_argument("--mission", help="mission name in the Zenoh keys (default: the scenario name)")
    p.add_argument("--key-file", type=Path, default=None, metavar="FILE",
                   help="use this mission key (copied in as mission.key) instead of a new one")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Resolve, check and write; returns the exit code."""
    args = build_parser().parse_args(argv)
    overrides = [*args.overrides, *([f"seed={args.seed}"] if args.seed is not None else [])]
    try:
        scenario = load_scenario(args.scenario, overrides)
        check_flood(scenario)
        mission = validate_mission(args.mission or scenario.name)
        paths = write_plans(scenario, args.mode, args.out, mission, args.key_file)
    except (ScenarioError, KeyNameError, KeyFileError) as exc:
        print(f"gcs.plan: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:
        print(f"gcs.plan: --out {args.out}: cannot write ({exc.strerror or exc})", file=sys.stderr)
        return EXIT_USAGE
    print(f"{scenario.name} ({args.mode}, seed {scenario.seed}): {len(paths.agents)} agent plans, "
          f"{paths.fleet.name}, {paths.cameras.name} and {paths.key.name} in {paths.folder}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
