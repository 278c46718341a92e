from pathlib import Path

import pytest

from gcs.processes.launch import ProcessOptions, agent_command
from vehicle_agents.__main__ import build_parser


def _agents_link_timeout_s(options: ProcessOptions) -> float:
    """The autopilot-silence timeout the agent process would run with, read by the agent's own parser."""
    command = agent_command(options, 3, Path("/runs/x/plan/agent_3.json"))
    assert command[0] == "vehicle_agents"
    return build_parser().parse_args(command[1:]).link_timeout


@pytest.mark.parametrize(("clock", "agent_timeout_s", "expected_s"), [
    ("paced", 2.0, 2.0),   # the defaults: the agents' own 2 s
    ("paced", 1.0, 2.0),   # a shorter agent timeout never shortens the link's
    ("paced", 10.0, 10.0),  # a host declared slow: its agents tolerate the same silence
    ("free", 10.0, 2.0),   # real-time faults: the agents keep a companion computer's 2 s
])
def test_a_paced_runs_agent_timeout_becomes_the_agents_link_timeout(clock: str, agent_timeout_s: float,
                                                                   expected_s: float) -> None:
    options = ProcessOptions(scenario_arg="circle", clock=clock, agent_timeout_s=agent_timeout_s)
    assert _agents_link_timeout_s(options) == expected_s
