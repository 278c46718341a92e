"""The fleet and camera processes read their plan files: PX4 parameters and response time from the fleet plan,
and a bad plan is one line with exit code 2 before any port is bound."""

from __future__ import annotations

from pathlib import Path

import pytest

from mission_plan.plan_files import write_plan
from mission_plan.plans import agent_plan, cameras_plan, fleet_plan
from mission_plan.scenario_files import load_scenario
from mock_autopilot.dynamics_params import px4_params
from mock_autopilot.sim_bridge import cameras as cameras_cli
from mock_autopilot.sim_bridge.__main__ import load_fleet_plan, main, vehicle_configs


def test_vehicle_configs_carry_the_plans_dynamics() -> None:
    scenario = load_scenario("circle", ["kinematics.response_time_s=0.6", "kinematics.max_xy_speed_mps=8",
                                        "altitude_m=12"])
    plan = fleet_plan(scenario)
    configs = vehicle_configs(plan)
    assert [c.sysid for c in configs] == [v.vehicle_id for v in scenario.vehicles]
    assert all(c.response_time_s == 0.6 for c in configs)
    assert all(dict(c.params) == px4_params(plan.kinematics, 12.0) for c in configs)
    assert configs[8].has_gps and configs[8].pad_enu_m == scenario.vehicles[8].pad_enu_m
    assert configs[0].home == scenario.home


def test_plan_or_local_scenario(tmp_path: Path) -> None:
    plan = fleet_plan(load_scenario("drift"))
    assert load_fleet_plan(write_plan(tmp_path / "fleet.json", plan), None, ()) == plan
    assert load_fleet_plan(None, "drift", ()) == plan


@pytest.mark.parametrize(("cli", "prefix"), [(main, "sim_bridge: "), (cameras_cli.main, "cameras: ")])
def test_bad_plan_is_one_line_and_exit_2(cli, prefix: str, tmp_path: Path,  # noqa: ANN001
                                         capsys: pytest.CaptureFixture[str]) -> None:
    scenario = load_scenario("circle")
    wrong = write_plan(tmp_path / "agent_1.json", agent_plan(scenario, 1, "paper"))
    for argv, message in (([str(tmp_path / "none.json")], "cannot read it"), ([str(wrong)], "holds plan 'agent/1'"),
                          ([str(wrong), "--scenario", "circle"], "--scenario and --set apply without it")):
        assert cli(["--plan", *argv]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and err.startswith(prefix) and message in err, err
    assert cli(["--scenario", "nonconvex"]) == 2
    assert '"auto" pads need the flood model' in capsys.readouterr().err


def test_cameras_plan_loads(tmp_path: Path) -> None:
    plan = cameras_plan(load_scenario("circle"))
    assert cameras_cli.load_cameras_plan(write_plan(tmp_path / "cameras.json", plan), None, ()) == plan
