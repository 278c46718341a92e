"""``python -m vehicle_agents --plan FILE``: the agent's configuration comes from its plan file alone, without the
ground station's code or the flood model; a bad plan is one line and exit code 2 (nothing is started)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from mission_plan.plan_files import write_plan
from mission_plan.plans import agent_plan
from mission_plan.scenario_files import load_scenario
from vehicle_agents.__main__ import EXIT_USAGE, build_parser, config_from_args, main

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def plan_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    scenario = load_scenario("circle", ["control_rate_hz=15", "altitude_m=12"])
    return write_plan(tmp_path_factory.mktemp("plan") / "agent_10.json", agent_plan(scenario, 10, "paper", "m7"))


def test_config_is_built_from_the_plan(plan_file: Path) -> None:
    args = build_parser().parse_args(["--plan", str(plan_file), "--speed", "2", "--link-timeout", "3"])
    config, mission, url = config_from_args(args)
    assert (config.vehicle_id, config.role, config.group, config.has_gps) == (10, "follower", None, False)
    assert config.params.mode == "paper" and len(config.params.roster) == 13
    assert config.control_rate_hz == 15.0 and config.speed == 2.0
    assert config.limits.takeoff_altitude_m == 12.0 and config.limits.link_timeout_s == 3.0
    assert len(config.pad_enu_m) == 2
    assert mission == "m7" and url == "udpin://0.0.0.0:14549"


def test_command_line_overrides_what_belongs_to_this_machine(plan_file: Path) -> None:
    args = build_parser().parse_args(["--plan", str(plan_file), "--rate-hz", "5", "--mission", "other",
                                      "--mavlink", "udpin://0.0.0.0:15000", "--id", "10", "--role", "follower"])
    config, mission, url = config_from_args(args)
    assert config.control_rate_hz == 5.0 and mission == "other" and url == "udpin://0.0.0.0:15000"


def test_scenario_convenience_matches_the_plan() -> None:
    args = build_parser().parse_args(["--id", "3", "--scenario", "circle", "--mode", "paper"])
    config, mission, _ = config_from_args(args)
    expected = agent_plan(load_scenario("circle"), 3, "paper")
    assert config.params == expected.params and mission == "circle"
    assert config.pad_enu_m == expected.vehicle.pad_enu_m[:2]


@pytest.mark.parametrize(("argv", "message"), [
    (["--plan", "{tmp}/missing.json"], "missing.json: cannot read it"),
    (["--plan", "{tmp}/broken.json"], "broken.json: not valid JSON"),
    (["--plan", "{plan}", "--id", "4"], "--id 4: the plan"),
    (["--plan", "{plan}", "--mode", "improved"], "was made for mode paper"),
    (["--plan", "{plan}", "--role", "leader"], "--role leader: the plan has vehicle 10 as follower"),
    (["--plan", "{plan}", "--scenario", "circle"], "--scenario and --set apply without it"),
    (["--plan", "{plan}", "--speed", "0"], "--speed 0.0: must be > 0"),
    (["--scenario", "circle"], "--id: required with --scenario"),
    (["--id", "1", "--scenario", "ellipse"], '"auto" pads need the flood model: use a plan file'),
    (["--id", "1", "--set", "radio.los=0.3"], "radio.los: unknown key (did you mean radio.loss?)"),
    (["--id", "99"], "--id 99: scenario circle has vehicles 1..13"),
    (["--plan", "{plan}"], "mission.key: cannot read it"),
    (["--id", "1", "--scenario", "circle"], "--key-file: required without --plan"),
    (["--plan", "{plan}", "--key-file", "{tmp}/broken.json"], "broken.json: readable by others"),
])
def test_bad_input_is_one_line_and_exit_2(argv: list[str], message: str, plan_file: Path, tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "broken.json").write_text("{")
    argv = [a.format(tmp=tmp_path, plan=plan_file) for a in argv]
    assert main(argv) == EXIT_USAGE
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("vehicle_agents: ") and message in err, err


def test_the_agent_never_imports_the_ground_station_or_builds_the_flood(plan_file: Path) -> None:
    code = (
        "import sys\n"
        "from vehicle_agents.__main__ import build_parser, config_from_args\n"
        f"config_from_args(build_parser().parse_args(['--plan', {str(plan_file)!r}]))\n"
        "config_from_args(build_parser().parse_args(['--id', '2', '--scenario', 'circle']))\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('gcs', 'mock_autopilot')))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=60, check=True)
    assert out.stdout.strip() == "[]", out.stdout


@pytest.mark.parametrize(("link", "loads_pymavlink"), [("mavsdk", False), ("pymavlink", True)])
def test_only_the_pymavlink_link_loads_pymavlink(link: str, loads_pymavlink: bool, plan_file: Path) -> None:
    """A MAVSDK agent reads mode names, never MAVLink numbers: pymavlink (~6 MiB per agent) stays out of its
    process, from the imports of ``python -m vehicle_agents`` through its links; ``--link pymavlink`` still loads it."""
    code = (
        "import sys\n"
        "from vehicle_agents.__main__ import _make_link, build_parser, config_from_args\n"
        "from vehicle_agents.sim_clock_link import SimClockLink\n"
        "from vehicle_agents.swarm_link_zenoh import ZenohSwarmLink\n"
        f"config, _, url = config_from_args(build_parser().parse_args(['--plan', {str(plan_file)!r}]))\n"
        f"_make_link({link!r}, url, config.control_rate_hz, config.has_gps)\n"
        "print(any(m.split('.')[0] == 'pymavlink' for m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=60, check=True)
    assert out.stdout.strip() == str(loads_pymavlink), out.stdout
