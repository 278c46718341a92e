"""``python -m vehicle_agents.perception frame.png --alt 10 --fov 60`` prints the result as JSON (real process)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import cv2

from mock_autopilot.camera.model import CameraModel
from mock_autopilot.camera.render import render_frame
from mock_autopilot.world.flood_model import ExpandingCircle

ROOT = Path(__file__).resolve().parents[3]


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "vehicle_agents.perception", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)


def test_prints_the_measurement_as_json(tmp_path: Path) -> None:
    # 16 m east at t = 30 s: the shore (radius 14 m) is 2 m west, water fills the west third of the image.
    frame = render_frame(ExpandingCircle(), 30.0, (16.0, 0.0, 10.0), 0.0, CameraModel(), seed=1)
    path = tmp_path / "frame.png"
    assert cv2.imwrite(str(path), frame.image_bgr)
    done = run(str(path), "--alt", "10", "--fov", "60")
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout)
    assert result["has_edge"] is True and not result["only_land"] and not result["only_water"]
    assert 0.25 < result["water_fraction"] < 0.4
    east, north = result["midpoint_offset_en_m"]
    assert -3.0 < east < -1.0 and abs(north) < 0.3, "the midpoint lies west of the drone, in metres"
    assert result["edge_normal_en"][0] > 0.95, "water -> land points east"
    assert len(result["edge_points_en_m"]) > 10


def test_unreadable_image_and_bad_arguments_exit_2(tmp_path: Path) -> None:
    (tmp_path / "not.png").write_text("nope")
    for args in ([str(tmp_path / "not.png"), "--alt", "10"], [str(tmp_path / "missing.png"), "--alt", "10"]):
        done = run(*args)
        assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1, done.stderr
    frame = tmp_path / "ok.png"
    assert cv2.imwrite(str(frame), render_frame(ExpandingCircle(), 0.0, (12.0, 0.0, 10.0), 0.0).image_bgr)
    for args in (["--alt", "nan"], ["--alt", "10", "--fov", "0"], ["--alt", "-1"]):
        done = run(str(frame), *args)
        assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1, (args, done.stderr)
