"""The live map's flags on ``gcs.mission`` and ``gcs.dashboard``: one line naming the flag, exit 2."""

from __future__ import annotations

import socket
import pytest

from gcs.dashboard.cli import main as dashboard_main
from gcs.dashboard.ports import choose_port, dashboard_url, is_loopback
from gcs.mission.cli import parse_options


def test_mission_flags_reach_the_options() -> None:
    assert parse_options(["circle"]).dashboard_port == 8080
    assert parse_options(["circle", "--no-dashboard"]).dashboard_port is None
    options = parse_options(["circle", "--dashboard-port", "0", "--dashboard-token", "t", "--dashboard-host", "0.0.0.0"])
    assert (options.dashboard_port, options.dashboard_token, options.dashboard_host) == (0, "t", "0.0.0.0")


@pytest.mark.parametrize(("args", "flag"), [
    (["--dashboard-port", "70000"], "--dashboard-port"),
    (["--dashboard-token", " "], "--dashboard-token"),
    (["--tiles", "/nonexistent/map.mbtiles"], "--tiles"),
    (["--tiles", "README.md"], "--tiles"),
])
def test_bad_mission_flags_exit_2_naming_the_flag(args: list[str], flag: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        parse_options(["circle", *args])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("gcs.mission: ") and flag in err and "\n" not in err


@pytest.mark.parametrize(("args", "flag"), [
    (["--mission", "a/b"], "--mission"),
    (["--mission", "circle", "--port", "-1"], "--dashboard-port"),
    (["--mission", "circle", "--connect", "nonsense"], "--connect"),
    (["--port", "8080"], "--mission"),
])
def test_bad_dashboard_flags_exit_2(args: list[str], flag: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        dashboard_main(args)
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("gcs.dashboard: ") and flag in err


def test_a_busy_port_gives_a_free_one_and_addresses_are_judged() -> None:
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        taken = busy.getsockname()[1]
        port = choose_port("127.0.0.1", taken)
        assert port != taken and port > 0
    assert is_loopback("127.0.0.1") and is_loopback("::1") and is_loopback("localhost")
    assert not is_loopback("0.0.0.0") and not is_loopback("192.168.1.5")
    assert dashboard_url("0.0.0.0", 8080) == "http://127.0.0.1:8080/"
