import math
from pathlib import Path

from gcs.processes.agent_exit_report import agent_refused_copies, perception_cpu_in_log, refused_copies_in_log

EXIT_LINE = ("2026-11-30 21:11:34,464 vehicle_agents INFO vehicle 7 exits with 0: 1202 control steps (20.0 Hz mission "
             "time), 0 overruns, 701 frames processed (perception 0.61 / 0.93 ms CPU per frame, p50 / p95), 0 frames "
             "missed; dropped for their tag: 0 commands, 0 states; "
             "relayed copies refused: 12")


def test_the_agent_still_writes_the_line_this_reads() -> None:
    source = (Path(__file__).resolve().parents[3] / "vehicle_agents" / "__main__.py").read_text()
    assert '"vehicle %d exits with %d: ' in source and 'relayed copies refused: %d"' in source
    assert '"(perception %.2f / %.2f ms CPU per frame, p50 / p95), ' in source


def test_the_count_is_read_from_the_agents_own_exit_line(tmp_path: Path) -> None:
    assert refused_copies_in_log("vehicle 7: mission -> holding\n" + EXIT_LINE + "\n", 7) == 12
    assert refused_copies_in_log(EXIT_LINE, 8) is None
    log = tmp_path / "agent_7.log"
    log.write_text("started\n" + EXIT_LINE.replace("refused: 12", "refused: 0") + "\n")
    assert agent_refused_copies(log, 7) == 0


def test_a_killed_agent_without_exit_line_stays_unknown(tmp_path: Path) -> None:
    log = tmp_path / "agent_3.log"
    log.write_text("2026-11-30 21:11:33,602 vehicle_agents INFO vehicle 3: mission -> holding\n")
    assert agent_refused_copies(log, 3) is None
    assert agent_refused_copies(tmp_path / "missing.log", 3) is None


def test_the_perception_cost_is_read_from_the_exit_line() -> None:
    assert perception_cpu_in_log(EXIT_LINE, 7) == (0.61, 0.93)
    assert perception_cpu_in_log(EXIT_LINE, 8) is None
    assert perception_cpu_in_log("vehicle 3: mission -> holding\n", 3) is None
    none_yet = EXIT_LINE.replace("0.61 / 0.93", "nan / nan")
    p50, p95 = perception_cpu_in_log(none_yet, 7)  # type: ignore[misc]
    assert math.isnan(p50) and math.isnan(p95)
