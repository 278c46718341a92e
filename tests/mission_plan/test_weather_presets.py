"""Weather presets: the specified numbers as defaults under the user's own keys; bad weather keys name the field."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import pytest

from mission_plan.jitter import jittered_pads, start_delays_s
from mission_plan.scenario_files import load_scenario
from mission_plan.table_fields import ScenarioError
from mission_plan.weather import SensorSpec, WindSpec
from mission_plan.weather_presets import PRESETS, apply_weather_preset

REPO = Path(__file__).resolve().parents[2]


def test_default_is_calm_still_air_exact_sensors_with_jitter() -> None:
    scenario = load_scenario("circle")
    assert scenario.weather == "calm"
    assert scenario.wind == WindSpec() and scenario.wind.still
    assert scenario.sensors == SensorSpec() and scenario.sensors.exact
    assert scenario.start_jitter_s == 0.2


def test_moderate_sets_the_specified_numbers() -> None:
    scenario = load_scenario("circle", ["weather=moderate"])
    assert scenario.wind == WindSpec(5.0, 270.0, "light", 3.0, 3.0, 20.0)
    assert scenario.sensors == SensorSpec(0.3, 0.5, 60.0, 0.2, 1.0, 0.01)


def test_rough_sets_the_specified_numbers() -> None:
    scenario = load_scenario("circle", ["weather=rough"])
    assert scenario.wind == WindSpec(9.0, 270.0, "moderate", 5.0, 3.0, 20.0)
    assert scenario.sensors == SensorSpec(0.6, 1.5, 60.0, 0.4, 3.0, 0.03)


def test_the_drones_know_their_own_odometry_and_ranging_figures() -> None:
    """The drift figure and the ranging σ reach every drone's control parameters; the ranging sensor is the
    drones' hardware, the same in every preset, and read only while the odometry drifts."""
    calm, moderate = load_scenario("circle", []), load_scenario("circle", ["weather=moderate"])
    params = moderate.control_params("improved")
    assert params.cooperative_position and params.odometry_drift_frac == 0.01 and params.ranging_sigma_m == 0.1
    assert not moderate.control_params("paper").cooperative_position
    assert calm.sensors.ranging_sigma_m == moderate.sensors.ranging_sigma_m
    assert moderate.sensors.ranging_used and not calm.sensors.ranging_used


def test_user_keys_win_over_the_preset_in_any_order() -> None:
    for overrides in (["weather=moderate", "wind.speed_mps=7"], ["wind.speed_mps=7", "weather=moderate"]):
        scenario = load_scenario("circle", overrides)
        assert scenario.wind.speed_mps == 7.0 and scenario.wind.turbulence == "light"


def test_preset_keys_of_unknown_tables_wait_for_their_schema() -> None:
    raw = {"weather": "rough", "imaging": {"jpeg_quality": 90}}
    without = apply_weather_preset(raw, {"wind", "sensors", "fleet"})
    assert without["imaging"] == {"jpeg_quality": 90}
    with_imaging = apply_weather_preset(raw, {"wind", "sensors", "fleet", "imaging"})
    expected = {key.split(".", 1)[1]: value for key, value in PRESETS["rough"].items() if key.startswith("imaging.")}
    assert with_imaging["imaging"] == {**expected, "jpeg_quality": 90}
    assert raw["imaging"] == {"jpeg_quality": 90}  # the caller's table is not changed


def test_every_preset_names_the_same_imaging_keys() -> None:
    keys = [sorted(k for k in table if k.startswith("imaging.")) for name, table in PRESETS.items() if name != "calm"]
    assert keys[0] == keys[1] and len(keys[0]) == 10


@pytest.mark.parametrize(("override", "message"), [
    ("weather=windy", "weather: unknown preset 'windy' (calm, moderate, rough)"),
    ("sensors.gps_white_sigma_m=-1", "sensors.gps_white_sigma_m: must be >= 0, got -1"),
    ("wind.turbulence=heavy", "wind.turbulence: must be one of none, light, moderate, severe, got 'heavy'"),
    ("wind.speed=3", "wind.speed: unknown key (did you mean wind.speed_mps?)"),
    ("fleet.pad_jitter_m=-0.1", "fleet.pad_jitter_m: must be >= 0, got -0.1"),
    ("sensors.gps_bias_tau_s=0", "sensors.gps_bias_tau_s: must be > 0, got 0"),
    ("sensors.ranging_sigma_m=-0.1", "sensors.ranging_sigma_m: must be >= 0, got -0.1"),
    ("sensors.ranging_rate_hz=0", "sensors.ranging_rate_hz: must be > 0, got 0"),
    ("control.ranging_sigma_m=0.2", "control.ranging_sigma_m: set by the scenario, not by the [control] table"),
])
def test_bad_weather_key_is_one_line_naming_the_field(override: str, message: str) -> None:
    with pytest.raises(ScenarioError) as info:
        load_scenario("circle", [override])
    assert str(info.value) == message


@pytest.mark.parametrize("override", ["weather=windy", "sensors.altitude_sigma_m=-0.2"])
def test_mission_cli_exits_2_naming_the_field(override: str) -> None:
    proc = subprocess.run([sys.executable, "-m", "gcs.mission", "circle", "--set", override], cwd=REPO,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"gcs.mission: {override.split('=')[0]}: "), proc.stderr


def test_jitter_is_seeded_bounded_and_seed_dependent() -> None:
    vehicles = load_scenario("circle", ["fleet.pad_jitter_m=0"]).vehicles
    one, again, other = (jittered_pads(vehicles, 0.2, seed) for seed in (1, 1, 2))
    assert one == again and one != other
    for moved, original in zip(one, vehicles):
        assert math.dist(moved.pad_enu_m[:2], original.pad_enu_m[:2]) <= 0.2
    ids = tuple(v.vehicle_id for v in vehicles)
    delays = start_delays_s(ids, 0.2, 1)
    assert delays == start_delays_s(ids, 0.2, 1) != start_delays_s(ids, 0.2, 2)
    assert all(0.0 <= d <= 0.2 for d in delays)
    assert jittered_pads(vehicles, 0.0, 1) == vehicles and not any(start_delays_s(ids, 0.0, 1))
