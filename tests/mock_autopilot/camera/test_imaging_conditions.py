"""The ``[imaging]`` conditions: each one changes the frame, one seed renders the same frame twice, two seeds
differ, the clean default leaves the scene untouched, and bad keys are one-line errors (exit 2 from a CLI)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mission_plan.imaging import ImagingSpec, imaging_spec, mean_wind_en_mps
from mission_plan.scenario_files import load_scenario
from mission_plan.table_fields import ScenarioError
from mock_autopilot.camera.imaging_conditions import water_is_turbid
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.camera.render import CameraPose, RenderedFrame, render_frame
from mock_autopilot.camera.truth import ACCURACY_FLOODS
from mock_autopilot.world.config import flood_model_from_config

ROOT = Path(__file__).resolve().parents[3]

ONE_AT_A_TIME = {
    "exposure_drift": ImagingSpec(exposure_drift=0.4),
    "white_balance_drift": ImagingSpec(white_balance_drift=0.2),
    "vignetting": ImagingSpec(vignetting=0.4),
    "noise_sigma": ImagingSpec(noise_sigma=6.0),
    "exposure_time_s": ImagingSpec(exposure_time_s=0.005),
    "jpeg_quality": ImagingSpec(jpeg_quality=60),
    "cloud_shadow_cover": ImagingSpec(cloud_shadow_cover=0.5),
    "sun_glint": ImagingSpec(sun_glint=True),
    "turbid_water_probability": ImagingSpec(turbid_water_probability=1.0),
    "floating_debris": ImagingSpec(floating_debris=True),
}
MIXED = ImagingSpec(exposure_drift=0.4, white_balance_drift=0.2, vignetting=0.4, noise_sigma=6.0,
                    exposure_time_s=0.005, jpeg_quality=60, cloud_shadow_cover=0.5, sun_glint=True,
                    turbid_water_probability=1.0, floating_debris=True)
POSE = CameraPose(vehicle_id=4, velocity_en_mps=(5.0, 0.0), wind_en_mps=(5.0, 0.0))


def frame(spec: ImagingSpec, seed: int = 3, t_s: float = 10.0, position: tuple[float, float, float] = (12.0, 0.0, 10.0),
          pose: CameraPose = POSE) -> RenderedFrame:
    """A frame over the circle's shore (water to the west); the glint and the shadows are placed by the seed."""
    flood = flood_model_from_config(ACCURACY_FLOODS["circle"])
    return render_frame(flood, t_s, position, 0.3, CameraModel(), seed, pose=pose, imaging=spec)


def test_clean_imaging_is_the_rendered_scene() -> None:
    assert ImagingSpec().is_clean
    np.testing.assert_array_equal(frame(ImagingSpec()).image_bgr, frame(ImagingSpec(), pose=CameraPose()).image_bgr)


@pytest.mark.parametrize("name", sorted(ONE_AT_A_TIME))
def test_each_condition_changes_the_frame_but_not_the_truth(name: str) -> None:
    spec = ONE_AT_A_TIME[name]
    # Over 200 s of a 5 m/s wind the drifting cloud shadows (half the ground) pass over the frame.
    times = [10.0] if name != "cloud_shadow_cover" else [float(t) for t in range(0, 200, 10)]
    changed_share = []
    for t_s in times:
        clean, hard = frame(ImagingSpec(), t_s=t_s), frame(spec, t_s=t_s)
        changed_share.append(float((np.abs(hard.image_bgr.astype(int) - clean.image_bgr.astype(int)).max(axis=2)
                                    > 0).mean()))
        np.testing.assert_array_equal(hard.water_mask, clean.water_mask)
    assert max(changed_share) > 0.001, f"{name} left the frame as it was"


def test_glint_and_debris_lie_on_the_water_and_turbid_water_is_brown() -> None:
    clean = frame(ImagingSpec())
    for spec in (ImagingSpec(sun_glint=True), ImagingSpec(floating_debris=True)):
        changed = np.abs(frame(spec).image_bgr.astype(int) - clean.image_bgr.astype(int)).max(axis=2) > 0
        assert not changed[~clean.water_mask].any()
    turbid = frame(ImagingSpec(turbid_water_probability=1.0))
    b, g, r = (turbid.image_bgr[turbid.water_mask][:, c].astype(float).mean() for c in range(3))
    assert r > g > b, "turbid water is tan, not blue"


def test_one_seed_gives_the_same_frame_twice_and_two_seeds_differ() -> None:
    a, b = frame(MIXED, seed=7), frame(MIXED, seed=7)
    np.testing.assert_array_equal(a.image_bgr, b.image_bgr)
    assert not np.array_equal(a.image_bgr, frame(MIXED, seed=8).image_bgr)
    # Per vehicle and per frame too: another drone, or the next frame, has its own noise.
    assert not np.array_equal(a.image_bgr, frame(MIXED, seed=7, pose=CameraPose(vehicle_id=5)).image_bgr)
    assert not np.array_equal(a.image_bgr, frame(MIXED, seed=7, t_s=10.1).image_bgr)


def test_turbid_water_is_drawn_for_the_stated_share_of_seeds() -> None:
    spec = ImagingSpec(turbid_water_probability=0.5)
    share = np.mean([water_is_turbid(spec, seed) for seed in range(400)])
    assert 0.42 < share < 0.58
    assert not any(water_is_turbid(ImagingSpec(), seed) for seed in range(50))


def test_cloud_shadows_drift_with_the_wind() -> None:
    spec = ImagingSpec(cloud_shadow_cover=0.5)
    still = CameraPose(vehicle_id=4)
    windy = CameraPose(vehicle_id=4, wind_en_mps=(6.0, 0.0))
    # At t = 0 the wind has moved nothing; 20 s later the field has moved 120 m in a 6 m/s wind.
    np.testing.assert_array_equal(frame(spec, t_s=0.0, pose=still).image_bgr,
                                  frame(spec, t_s=0.0, pose=windy).image_bgr)
    assert not np.array_equal(frame(spec, t_s=20.0, pose=still).image_bgr, frame(spec, t_s=20.0, pose=windy).image_bgr)


def test_motion_blur_grows_with_speed() -> None:
    spec = ImagingSpec(exposure_time_s=0.05)

    def sharpness(speed_mps: float) -> float:
        image = frame(spec, pose=CameraPose(velocity_en_mps=(speed_mps, 0.0))).image_bgr.astype(float)
        return float(np.abs(np.diff(image, axis=1)).mean())

    assert sharpness(0.0) > sharpness(2.0) > sharpness(8.0)


@pytest.mark.parametrize(("table", "message"), [
    ({"noise_sigma": -1.0}, "imaging.noise_sigma: must be >= 0"),
    ({"jpeg_quality": 101}, "imaging.jpeg_quality: must be 0 (no JPEG) or 1..100"),
    ({"jpeg_quality": 2.5}, "imaging.jpeg_quality: must be an integer"),
    ({"vignetting": 1.5}, "imaging.vignetting: must be <= 1"),
    ({"sun_glint": "yes"}, "imaging.sun_glint: must be true or false"),
    ({"exposure_drift": 0.95}, "imaging.exposure_drift: must be <= 0.9"),
    ({"turbid_water": 1.0}, "imaging.turbid_water: unknown key (did you mean imaging.turbid_water_probability?)"),
])
def test_bad_imaging_keys_name_the_field(table: dict[str, object], message: str) -> None:
    with pytest.raises(ScenarioError) as info:
        imaging_spec(table)
    assert str(info.value).startswith(message)


def test_scenario_reads_imaging_keys_and_defaults_to_clean() -> None:
    assert load_scenario("circle").imaging.is_clean
    s = load_scenario("circle", ["imaging.noise_sigma=3", "imaging.sun_glint=true", "imaging.jpeg_quality=80"])
    assert s.imaging == ImagingSpec(noise_sigma=3.0, sun_glint=True, jpeg_quality=80)
    assert mean_wind_en_mps(s) == (0.0, 0.0)


def test_mean_wind_blows_from_the_stated_direction() -> None:
    class Wind:
        speed_mps, from_deg = 5.0, 270.0

    class WithWind:
        wind = Wind()

    east, north = mean_wind_en_mps(WithWind())
    assert east == pytest.approx(5.0) and north == pytest.approx(0.0, abs=1e-9)


def test_a_bad_imaging_key_exits_2_from_the_command_line(tmp_path: Path) -> None:
    out = tmp_path / "plans"
    proc = subprocess.run([sys.executable, "-m", "gcs.plan", "circle", "--set", "imaging.noise_sigma=-3", "--out",
                           str(out)], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "imaging.noise_sigma: must be >= 0" in lines[0], proc.stderr
    assert not out.exists()
