"""The CLI: usage errors give one line and exit 2; a real process serves MAVLink and stops cleanly (ports 20500-20549)."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from mock_autopilot.cli import build_parser, options_from_args, parse_id_list, run, vehicle_configs

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("argv,needle", [
    (["--vehicles", "0"], "--vehicles"),
    (["--vehicles", "2", "--speed", "0"], "--speed"),
    (["--vehicles", "2", "--param", "NOPE=1"], "NOPE"),
    (["--vehicles", "2", "--param", "COM_OBL_RC_ACT=9"], "COM_OBL_RC_ACT"),
    (["--vehicles", "2", "--param", "MIS_TAKEOFF_ALT"], "NAME=VALUE"),
    (["--vehicles", "2", "--no-gps-for", "5"], "--no-gps-for"),
    (["--vehicles", "2", "--no-gps-for", "x"], "--no-gps-for"),
    (["--vehicles", "2", "--signing-key", "abc"], "--signing-key"),
    (["--vehicles", "2", "--fault", "explode:1@3"], "fault"),
    (["--vehicles", "2", "--fault", "kill:7@3"], "--fault"),
    (["--vehicles", "2", "--fault", "battery:1@3"], "VALUE"),
    (["--vehicles", "2", "--home", "99,0,0"], "--home"),
    (["--vehicles", "2", "--base-port", "70000"], "--base-port"),
])
def test_usage_errors_print_one_line_and_exit_2(argv: list[str], needle: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert run(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0]


def test_options_become_vehicle_configs() -> None:
    args = build_parser().parse_args(["--vehicles", "4", "--no-gps-for", "1,3", "--param", "MPC_XY_VEL_MAX=5", "--pad-spacing-m", "1.5"])
    configs = vehicle_configs(options_from_args(args))
    assert [c.has_gps for c in configs] == [True, False, True, False]
    assert [c.sysid for c in configs] == [1, 2, 3, 4]
    assert [c.pad_enu_m[0] for c in configs] == [0.0, 1.5, 3.0, 4.5]
    assert all(c.params["MPC_XY_VEL_MAX"] == 5.0 for c in configs)
    assert parse_id_list("0,2,5-7") == {0, 2, 5, 6, 7}


@pytest.mark.integration
def test_cli_process_serves_mavlink_and_exits_cleanly_on_sigterm() -> None:
    os.environ["MAVLINK20"] = "1"
    from pymavlink import mavutil

    mavutil.set_dialect("common")
    client = mavutil.mavlink_connection("udpin:127.0.0.1:20501", source_system=255)
    proc = subprocess.Popen(
        [sys.executable, "-m", "mock_autopilot", "--vehicles", "2", "--base-port", "20500", "--gcs-port", "20540",
         "--speed", "2", "--no-gps-for", "1", "--fault", "gps:0@1"],
        cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    try:
        hb = client.wait_heartbeat(timeout=10)
        assert hb is not None and client.target_system == 2
        client.mav.command_long_send(2, 1, 400, 0, 1, 0, 0, 0, 0, 0, 0)
        ack = client.recv_match(type="COMMAND_ACK", blocking=True, timeout=3)
        assert ack is not None and ack.result == 0
        client.write(b"\xfd\x01garbage")
        time.sleep(0.3)
        proc.send_signal(signal.SIGTERM)
        out, err = proc.communicate(timeout=10)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        client.close()
    assert proc.returncode == 0
    assert "2 vehicle(s)" in out
    assert "system 2 drops" in err and "truncated" in err
