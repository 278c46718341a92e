"""``python -m mock_autopilot.camera``: the preview a user runs to see what a drone sees (real process)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np

ROOT = Path(__file__).resolve().parents[3]


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "mock_autopilot.camera", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)


def test_preview_writes_the_frame_and_the_truth_mask(tmp_path: Path) -> None:
    out = tmp_path / "frame.png"
    done = run("--scenario", "circle", "--t", "30", "--east", "16", "--north", "0", "--alt", "10", "--out", str(out),
               "--mask")
    assert done.returncode == 0, done.stderr
    image = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    mask = cv2.imread(str(tmp_path / "frame_mask.png"), cv2.IMREAD_UNCHANGED)
    assert image.shape == (128, 128, 3) and mask.shape == (128, 128)
    # 16 m east at t = 30 s: the 14 m shore is 2 m west of the drone, so about a third of the frame is water.
    assert 0.25 < float(np.mean(mask > 0)) < 0.4
    assert str(out) in done.stdout


def test_preview_bad_input_is_one_line_and_exit_2(tmp_path: Path) -> None:
    for args in (["--scenario", "no_such_scenario"], ["--alt", "-3"], ["--t", "nan"],
                 ["--out", str(tmp_path / "missing_dir" / "x.png")]):
        done = run(*args, "--out", str(tmp_path / "x.png")) if "--out" not in args else run(*args)
        assert done.returncode == 2, (args, done.stderr)
        assert len(done.stderr.strip().splitlines()) == 1, done.stderr


def test_preview_set_overrides_like_the_mission_and_names_the_field(tmp_path: Path) -> None:
    pose = ("--scenario", "circle", "--t", "30", "--east", "16", "--alt", "10")
    plain, hard = tmp_path / "plain.png", tmp_path / "hard.png"
    assert run(*pose, "--out", str(plain)).returncode == 0
    done = run(*pose, "--out", str(hard), "--set", "weather=moderate", "--set", "imaging.turbid_water_probability=1")
    assert done.returncode == 0, done.stderr
    a, b = cv2.imread(str(plain)).astype(int), cv2.imread(str(hard)).astype(int)
    assert np.abs(a - b).mean() > 5.0, "the moderate preset's imaging (turbid water, noise, JPEG) changes the frame"
    for assignment, field in (("weather=stormy", "weather"), ("imaging.noise_sigma=-1", "imaging.noise_sigma"),
                              ("flood.radius=3", "flood.radius"), ("imaging", "--set")):
        done = run(*pose, "--out", str(tmp_path / "x.png"), "--set", assignment)
        assert done.returncode == 2, (assignment, done.stderr)
        lines = done.stderr.strip().splitlines()
        assert len(lines) == 1 and field in lines[0], (assignment, done.stderr)
