"""PX4's mode names without MAVLink numbers: MAVSDK's names for every mode, the same objects through comms.px4, and
no pymavlink behind them (the point of the module: a MAVSDK agent imports it alone)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from mavsdk.plugins.telemetry import FlightMode

import comms.px4 as px4
from comms.px4_mode_names import MAVSDK_MODE_NAMES, MAVSDK_NAMES, MAVSDK_OFFBOARD, Px4Mode

REPO = Path(__file__).resolve().parents[2]


def test_every_mode_has_a_name_mavsdk_reports() -> None:
    assert set(MAVSDK_NAMES) == set(Px4Mode)
    assert set(MAVSDK_NAMES.values()) <= set(FlightMode.__members__)
    assert MAVSDK_OFFBOARD == FlightMode.OFFBOARD.name
    assert MAVSDK_MODE_NAMES == {mode.value: name for mode, name in MAVSDK_NAMES.items()}


def test_the_mode_table_and_comms_px4_use_these_names() -> None:
    assert all(spec.mavsdk_name == MAVSDK_NAMES[mode] for mode, spec in px4.MODE_TABLE.items())
    assert set(px4.MODE_TABLE) == set(Px4Mode)
    assert px4.Px4Mode is Px4Mode
    assert px4.MAVSDK_MODE_NAMES is MAVSDK_MODE_NAMES and px4.MAVSDK_OFFBOARD is MAVSDK_OFFBOARD


def _mavlink_modules_after(statement: str) -> list[str]:
    """The pymavlink modules a fresh interpreter holds after running ``statement`` from the repository."""
    code = (f"import json, sys\n{statement}\n"
            "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] == 'pymavlink')))\n")
    out = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=60, check=True)
    return json.loads(out.stdout)


def test_the_names_do_not_load_pymavlink_and_comms_px4_does() -> None:
    assert _mavlink_modules_after("import comms.px4_mode_names") == []
    assert "pymavlink.dialects.v20.common" in _mavlink_modules_after("import comms.px4")
