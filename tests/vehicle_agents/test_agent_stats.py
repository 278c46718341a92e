"""The agent's counters for its exit line: the perception's CPU per frame."""

import math

from vehicle_agents.agent import AgentStats


def test_perception_cpu_percentiles_in_milliseconds() -> None:
    stats = AgentStats(perception_cpu_s=[0.001 * k for k in range(1, 101)])
    p50, p95 = stats.perception_cpu_ms()
    assert math.isclose(p50, 50.5) and math.isclose(p95, 95.05)


def test_no_frame_perceived_gives_nan() -> None:
    p50, p95 = AgentStats().perception_cpu_ms()
    assert math.isnan(p50) and math.isnan(p95)
