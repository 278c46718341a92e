"""Plans and plan files: each child's slice of a scenario survives encoding exactly, and a bad file is one line."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from mission_plan.plan_files import PlanFileError, decode_plan, encode_plan, read_plan, write_plan
from mission_plan.plans import AgentPlan, CamerasPlan, FleetPlan, agent_plan, cameras_plan, fleet_plan
from mission_plan.scenario_files import load_scenario
from mission_plan.scenarios import SCENARIO_DIR
from mission_plan.table_fields import ScenarioError


@pytest.fixture(scope="module")
def circle():  # noqa: ANN201
    return load_scenario("circle", ["kinematics.response_time_s=0.6", "seed=4"])


def test_agent_plan_round_trip_and_content(circle) -> None:  # noqa: ANN001
    plan = agent_plan(circle, 9, "improved", mission="m1")
    decoded = decode_plan(encode_plan(plan), AgentPlan)
    assert decoded == plan
    assert decoded.vehicle == circle.vehicles[8] and decoded.vehicle.role == "leader" and decoded.vehicle.has_gps
    assert decoded.params == circle.control_params("improved") and len(decoded.params.roster) == 13
    assert (decoded.mission, decoded.scenario, decoded.seed) == ("m1", "circle", 4)
    assert decoded.control_rate_hz == circle.control_rate_hz and decoded.altitude_m == circle.altitude_m
    assert decoded.camera == circle.camera and decoded.home == circle.home


def test_fleet_and_cameras_plans_round_trip(circle) -> None:  # noqa: ANN001
    fleet = fleet_plan(circle)
    assert decode_plan(encode_plan(fleet), FleetPlan) == fleet
    assert fleet.kinematics.response_time_s == 0.6 and fleet.vehicles == circle.vehicles
    assert Path(fleet.world.source_dir).is_absolute() and Path(fleet.world.source_dir) == SCENARIO_DIR
    cameras = cameras_plan(circle)
    assert decode_plan(encode_plan(cameras), CamerasPlan) == cameras
    assert cameras.roles == {v.vehicle_id: v.role for v in circle.vehicles}
    assert cameras.world.flood == dict(circle.flood) and cameras.world.seed == 4


def test_plan_files_are_readable_json(circle, tmp_path: Path) -> None:  # noqa: ANN001
    path = write_plan(tmp_path / "deep" / "agent_1.json", agent_plan(circle, 1, "paper"))
    text = path.read_text()
    assert json.loads(text)["plan"] == "agent/1" and "\n" in text.strip()
    assert read_plan(path, AgentPlan).params.mode == "paper"


def _mutated(plan: AgentPlan, edit) -> bytes:  # noqa: ANN001
    raw = json.loads(encode_plan(plan))
    edit(raw)
    return json.dumps(raw).encode()


@pytest.mark.parametrize(("edit", "message"), [
    (lambda raw: raw["vehicle"].update(rnak=1), "vehicle.rnak: unknown key (did you mean vehicle.rank?)"),
    (lambda raw: raw["params"].update(encircle_sped_mps=2.0),
     "params.encircle_sped_mps: unknown key (did you mean params.encircle_speed_mps?)"),
    (lambda raw: raw["params"]["roster"][2].update(gruop="A"),
     "params.roster[2].gruop: unknown key (did you mean params.roster[2].group?)"),
    (lambda raw: raw.update(altitude=3), "altitude: unknown key (did you mean altitude_m?)"),
    (lambda raw: raw.update(plan="fleet/1"), "holds plan 'fleet/1', expected 'agent/1'"),
    (lambda raw: raw.pop("plan"), "not a FloodWatch plan"),
    (lambda raw: raw["camera"].update(fov_deg="wide"), "Expected `float`, got `str` - at `$.camera.fov_deg`"),
    (lambda raw: raw.pop("home"), "missing required field `home`"),
    (lambda raw: raw.update(control_rate_hz=0), "control_rate_hz: must be > 0"),
    (lambda raw: raw["params"].update(separation_distance_m=-1), "control.separation_distance_m: must be > 0"),
    (lambda raw: raw["vehicle"].update(role="follower"), "not in the roster as a follower"),
])
def test_bad_plans_give_one_line(circle, edit, message: str) -> None:  # noqa: ANN001
    with pytest.raises(PlanFileError) as info:
        decode_plan(_mutated(agent_plan(circle, 3, "improved"), edit), AgentPlan)
    assert message in str(info.value) and "\n" not in str(info.value)


def test_unreadable_and_invalid_files_name_the_file(tmp_path: Path) -> None:
    with pytest.raises(PlanFileError, match="missing.json: cannot read it"):
        read_plan(tmp_path / "missing.json", FleetPlan)
    broken = tmp_path / "broken.json"
    broken.write_text('{"plan": "fleet/1", ')
    with pytest.raises(PlanFileError, match="broken.json: not valid JSON"):
        read_plan(broken, FleetPlan)


def test_fleet_plan_checks_its_vehicles(circle) -> None:  # noqa: ANN001
    fleet = fleet_plan(circle)
    twice = json.loads(encode_plan(fleet))
    twice["vehicles"][1]["vehicle_id"] = 1
    with pytest.raises(PlanFileError, match="vehicle ids must be unique"):
        decode_plan(json.dumps(twice).encode(), FleetPlan)
    with pytest.raises(ValueError, match="no vehicle"):
        FleetPlan(**{**{f: getattr(fleet, f) for f in FleetPlan.__struct_fields__}, "vehicles": ()})


def test_agent_plan_for_an_unknown_vehicle(circle) -> None:  # noqa: ANN001
    with pytest.raises(ScenarioError, match="--id 14: scenario circle has vehicles 1..13"):
        agent_plan(circle, 14, "paper")


@pytest.mark.parametrize(("key", "value", "message"), [
    ("noise_sigma", -1.0, "imaging.noise_sigma: must be >= 0"),
    ("jpeg_quality", 101, "imaging.jpeg_quality: must be 0 (no JPEG) or 1..100"),
    ("cloud_shadow_cover", 1.5, "imaging.cloud_shadow_cover: must be <= 1"),
    ("exposure_drift", 0.95, "imaging.exposure_drift: must be <= 0.9"),
])
def test_a_cameras_plan_range_checks_its_imaging(circle, tmp_path: Path, key: str, value: object,  # noqa: ANN001
                                                 message: str) -> None:
    raw = json.loads(encode_plan(cameras_plan(circle)))
    raw["imaging"] = dict(raw["imaging"], **{key: value})
    path = tmp_path / "cameras.json"
    path.write_text(json.dumps(raw))
    with pytest.raises(PlanFileError) as info:
        read_plan(path, CamerasPlan)
    assert message in str(info.value) and str(path) in str(info.value)
    assert len(str(info.value).splitlines()) == 1
