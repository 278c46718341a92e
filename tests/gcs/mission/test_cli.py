"""``python -m gcs.mission``: flags, one-line errors with exit code 2, and a real lockstep run writing outputs."""

import subprocess
import sys
from pathlib import Path

import pytest

from gcs.mission.cli import default_out_dir, main, parse_options

REPO = Path(__file__).resolve().parents[3]


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["atlantis", "--engine", "lockstep"], "unknown scenario"),
        (["circle", "--engine", "lockstep", "--set", "radio.range_m=-5"], "radio.range_m"),
        (["circle", "--engine", "lockstep", "--set", "oops"], "key=value"),
        (["circle", "--engine", "lockstep", "--duration", "-1"], "--duration"),
        (["circle", "--engine", "lockstep", "--speed", "0"], "--speed"),
        (["circle", "--mode", "magic"], "--mode"),
        (["circle", "--engine", "warp"], "--engine"),
        (["circle", "--seed", "x"], "--seed"),
        (["circle", "--engine", "lockstep", "--set", "flood.radius_start_m=-3"], "flood.radius_start_m"),
        (["circle", "--backend", "px4"], "--backend"),
        (["circle", "--engine", "lockstep", "--backend", "gazebo"], "--backend"),
        (["circle", "--key-file", "/nonexistent/mission.key"], "--key-file: key file /nonexistent/mission.key"),
        (["circle", "--startup-timeout-s", "0"], "--startup-timeout-s"),
        (["circle", "--startup-timeout-s", "-5"], "--startup-timeout-s"),
        (["circle", "--startup-timeout-s", "inf"], "--startup-timeout-s"),
        (["circle", "--startup-timeout-s", "nan"], "--startup-timeout-s"),
        (["circle", "--startup-timeout-s", "soon"], "--startup-timeout-s"),
    ],
)
def test_bad_input_prints_one_line_and_exits_2(argv: list[str], needle: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as info:
        sys.exit(main(argv))
    assert info.value.code == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and len(err.splitlines()) == 1


def test_unknown_key_in_a_toml_file_stops_both_engines_before_anything_starts(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from gcs.scenario import SCENARIO_DIR

    path = tmp_path / "typo.toml"
    path.write_text((SCENARIO_DIR / "circle.toml").read_text().replace("range_m = 25.0", "rang_m = 25.0"))
    for engine in ("processes", "lockstep"):
        out = tmp_path / f"run-{engine}"
        assert main([str(path), "--engine", engine, "--out", str(out), "--no-live"]) == 2
        err = capsys.readouterr().err.strip()
        assert err == "gcs.mission: radio.rang_m: unknown key (did you mean radio.range_m?)"
        assert not out.exists(), "nothing may start or be written"


def test_seed_is_applied_before_resolution() -> None:
    from gcs.mission.cli import resolve_scenario

    scenario = resolve_scenario(parse_options(["terrain", "--seed", "9", "--duration", "7"]))
    assert scenario.seed == 9 and scenario.duration_s == 7.0


def test_options_and_default_out_dir() -> None:
    opts = parse_options(["circle", "--engine", "lockstep", "--mode", "improved", "--seed", "7", "--duration", "5",
                          "--set", "radio.loss=0.1", "--set", "flood.radius_end_m=18"])
    assert opts.engine == "lockstep" and opts.mode == "improved" and opts.seed == 7 and opts.duration_s == 5.0
    assert opts.overrides == ("radio.loss=0.1", "flood.radius_end_m=18")
    assert parse_options(["circle"]).engine == "processes"
    out = default_out_dir("circle", "lockstep", "paper")
    assert out.parent == Path("runs") and out.name.endswith("-circle-lockstep-paper")


def test_startup_timeout_reaches_the_processes_engine() -> None:
    from gcs.processes import process_options
    from gcs.scenario import load_scenario

    scenario = load_scenario("circle")
    assert process_options(scenario, parse_options(["circle"])).startup_timeout_s == 60.0
    assert process_options(scenario, parse_options(["circle", "--startup-timeout-s", "7.5"])).startup_timeout_s == 7.5


@pytest.mark.parametrize("backend", ["kinematic", "px4"])
def test_lockstep_run_writes_the_mission_outputs(tmp_path: Path, backend: str) -> None:
    out = tmp_path / "run"
    proc = subprocess.run(
        [sys.executable, "-m", "gcs.mission", "circle", "--engine", "lockstep", "--mode", "improved", "--seed", "2",
         "--duration", "4", "--out", str(out), "--backend", backend],
        cwd=REPO, capture_output=True, text=True, timeout=240,
    )
    assert proc.returncode == 0, proc.stderr
    for name in ("metrics.json", "polygons.geojson", "polygons.kml", "trajectories.png", "events.log"):
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    assert "outputs:" in proc.stdout and f"backend={backend}" in proc.stdout
    events = (out / "events.log").read_text().splitlines()
    assert events[0].startswith("t=   0.00s lockstep start: circle") and "lockstep end after" in events[-1]
    assert "t=   4.00s relayed copies refused as impossible: 0 by the vehicles" in events
