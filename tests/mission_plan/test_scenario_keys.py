"""Unknown keys are errors in every table of a scenario, by ``--set`` or in a TOML file: one line naming the key
and the closest known key; and a scenario read without the flood model refuses "auto" pads."""

from __future__ import annotations

from pathlib import Path

import pytest

from mission_plan.control_params import ControlParamsError, params_for_mode
from mission_plan.scenario_files import load_scenario
from mission_plan.scenarios import SCENARIO_DIR, scenario_names
from mission_plan.table_fields import ScenarioError
from mission_plan.unknown_keys import unknown_key_message


def test_message_names_the_closest_key_or_lists_the_known_ones() -> None:
    assert unknown_key_message("radio", "los", ["range_m", "loss"]) == "radio.los: unknown key (did you mean radio.loss?)"
    assert unknown_key_message("", "sed", ["seed", "name"]) == "sed: unknown key (did you mean seed?)"
    assert unknown_key_message("radio", "zzz", ["loss", "range_m"]) == "radio.zzz: unknown key (known: loss, range_m)"


@pytest.mark.parametrize(("override", "message"), [
    ("radio.los=0.3", "radio.los: unknown key (did you mean radio.loss?)"),
    ("radio.nonsense=3", "radio.nonsense: unknown key (known: bandwidth_bytes_per_s, burst_gap_s, burst_loss, burst_mean_s, edge_loss, edge_loss_exponent, gcs_lossless, jitter_s, latency_s, loss, range_m)"),
    ("duration=5", "duration: unknown key (did you mean duration_s?)"),
    ("home.lat=5", "home.lat: unknown key (did you mean home.lat_deg?)"),
    ("fleet.leader=2", "fleet.leader: unknown key (did you mean fleet.leaders?)"),
    ("camera.fov=50", "camera.fov: unknown key (did you mean camera.fov_deg?)"),
    ("kinematics.response_time=0.6", "kinematics.response_time: unknown key (did you mean kinematics.response_time_s?)"),
    ("control.encircle_speed=2", "control.encircle_speed: unknown key (did you mean control.encircle_speed_mps?)"),
    ("control.paper.safety_radius=2",
     "control.paper.safety_radius: unknown key (did you mean control.paper.safety_radius_m?)"),
    ("control.improved.meet_distance=2",
     "control.improved.meet_distance: unknown key (did you mean control.improved.meet_distance_m?)"),
    ("control.fov_deg=30", "control.fov_deg: set by the scenario, not by the [control] table"),
    ("radio.loss.x=1", "radio.loss: is not a table"),
])
def test_unknown_override_is_one_line_with_a_suggestion(override: str, message: str) -> None:
    with pytest.raises(ScenarioError) as info:
        load_scenario("circle", [override])
    assert str(info.value) == message or str(info.value).startswith(message)
    assert "\n" not in str(info.value)


def test_unknown_key_in_a_toml_file(tmp_path: Path) -> None:
    text = (SCENARIO_DIR / "circle.toml").read_text().replace("jitter_s = 0.0", "jiter_s = 0.0")
    path = tmp_path / "typo.toml"
    path.write_text(text)
    with pytest.raises(ScenarioError, match=r"^radio\.jiter_s: unknown key \(did you mean radio\.jitter_s\?\)$"):
        load_scenario(str(path))


def test_control_table_errors_without_a_scenario() -> None:
    with pytest.raises(ControlParamsError, match=r"control\.paper: must be a table"):
        params_for_mode("paper", {"paper": 3}, ())
    with pytest.raises(ControlParamsError, match=r"control\.rate_hz: unknown key"):
        params_for_mode("improved", {"rate_hz": 20}, ())


def test_bundled_scenarios_without_the_flood_model() -> None:
    """circle, drift and large have explicit pads; ellipse, nonconvex and terrain need the ground station."""
    assert set(scenario_names()) >= {"circle", "ellipse", "nonconvex", "drift", "terrain", "large"}
    for name in ("circle", "drift", "large"):
        assert load_scenario(name).vehicles
    for name in ("ellipse", "nonconvex", "terrain"):
        with pytest.raises(ScenarioError, match=r'^fleet\.launch_en_m: "auto" pads need the flood model: use a plan'):
            load_scenario(name)
    assert load_scenario(str(SCENARIO_DIR / "circle.toml")).name == "circle"


def test_resolver_fills_in_auto_pads() -> None:
    def resolve(fleet, flood, seed, source_dir):  # noqa: ANN001, ANN202
        assert flood["model"] == "ellipse" and seed == 1 and source_dir == SCENARIO_DIR
        return {**fleet, "launch_en_m": [20.0, 0.0]}

    scenario = load_scenario("ellipse", ["fleet.pad_jitter_m=0"], resolve_launch=resolve)  # unjittered pads
    assert len(scenario.vehicles) == 16 and scenario.vehicles[0].pad_enu_m[0] == pytest.approx(20.0)
