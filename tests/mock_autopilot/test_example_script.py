"""The new-user path: ``python -m mock_autopilot --vehicles 1`` + ``examples/fly_one_vehicle.py`` (ports 20550-20599)."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
@pytest.mark.integration
def test_example_flies_against_the_cli_fleet() -> None:
    fleet = subprocess.Popen(
        [sys.executable, "-m", "mock_autopilot", "--vehicles", "1", "--base-port", "20550", "--gcs-port", "20590"],
        cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    try:
        result = subprocess.run(
            [sys.executable, "examples/fly_one_vehicle.py", "--url", "udpin://0.0.0.0:20550", "--speed", "2", "--seconds", "2"],
            cwd=ROOT, capture_output=True, text=True, timeout=120,
        )
    finally:
        fleet.terminate()
        fleet.communicate(timeout=10)
    assert result.returncode == 0, result.stderr[-2000:]
    assert "landed and disarmed" in result.stdout
    north = float(result.stdout.split("offboard: flew ")[1].split(" m north")[0])
    assert north == pytest.approx(4.0, abs=0.6)
