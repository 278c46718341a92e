"""``python -m gcs.plan``: the ground station's resolution written as plan files, and one-line errors."""

from __future__ import annotations

import stat
import subprocess
import sys
from pathlib import Path

import pytest

from comms.key_file import create_key_file, read_key_file
from gcs.plan.__main__ import main
from gcs.plan.files import plan_paths, write_plans
from gcs.scenario import load_scenario
from mission_plan.plan_files import read_plan
from mission_plan.plans import AgentPlan, CamerasPlan, FleetPlan, agent_plan

REPO = Path(__file__).resolve().parents[3]


def test_writes_every_plan_of_an_auto_pad_scenario(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["ellipse", "--out", str(tmp_path), "--mode", "paper", "--seed", "5", "--set", "radio.range_m=30"]) == 0
    assert "16 agent plans" in capsys.readouterr().out
    scenario = load_scenario("ellipse", ["radio.range_m=30", "seed=5"])
    paths = plan_paths(tmp_path, range(1, 17))
    for vid, path in paths.agents.items():
        assert read_plan(path, AgentPlan) == agent_plan(scenario, vid, "paper")
    fleet = read_plan(paths.fleet, FleetPlan)
    assert fleet.vehicles == scenario.vehicles and fleet.seed == 5
    assert read_plan(paths.cameras, CamerasPlan).roles[1] == "boundary"


def test_write_plans_names_the_files(tmp_path: Path) -> None:
    paths = write_plans(load_scenario("circle"), "improved", tmp_path / "plan", mission="run7")
    assert sorted(p.name for p in (tmp_path / "plan").iterdir()) == sorted(
        ["fleet.json", "cameras.json", "mission.key", *(f"agent_{i}.json" for i in range(1, 14))])
    assert read_plan(paths.agents[4], AgentPlan).mission == "run7"
    assert stat.S_IMODE(paths.key.stat().st_mode) == 0o600


def test_a_given_key_travels_with_the_plans_and_each_mission_gets_its_own_otherwise(tmp_path: Path) -> None:
    given = create_key_file(tmp_path / "ops.key")
    paths = write_plans(load_scenario("circle"), "improved", tmp_path / "a", key_file=tmp_path / "ops.key")
    assert read_key_file(paths.key) == given
    other = write_plans(load_scenario("circle"), "improved", tmp_path / "b")
    assert read_key_file(other.key) != given


@pytest.mark.parametrize(("argv", "message"), [
    (["circle", "--set", "radio.los=0.3"], "gcs.plan: radio.los: unknown key (did you mean radio.loss?)"),
    (["circle", "--set", "flood.radius_ends_m=3"], "gcs.plan: flood.radius_ends_m: unknown key for model 'circle'"),
    (["atlantis"], "gcs.plan: scenario: unknown scenario 'atlantis'"),
    (["circle", "--mission", "a/b"], "gcs.plan: mission name 'a/b'"),
    (["circle", "--mode", "magic"], "gcs.plan: argument --mode: invalid choice"),
])
def test_bad_input_is_one_line_and_exit_2(argv: list[str], message: str, tmp_path: Path) -> None:
    out = tmp_path / "plans"
    proc = subprocess.run([sys.executable, "-m", "gcs.plan", *argv, "--out", str(out)], cwd=REPO,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(message), proc.stderr
    assert not out.exists()
