"""The host-capacity estimate warns on the runs that did not hold real time on 2 cores and not on those that did."""

import pytest

from gcs.processes.host_capacity import estimate_capacity


@pytest.mark.parametrize(
    "vehicles, control_rate_hz, speed",
    [(13, 20.0, 1.0), (13, 20.0, 1.25), (16, 20.0, 1.0), (19, 10.0, 1.0), (25, 5.0, 1.0)],
)
def test_runs_that_held_on_two_cores_get_no_warning(vehicles: int, control_rate_hz: float, speed: float) -> None:
    estimate = estimate_capacity(vehicles, control_rate_hz, speed, available_cores=2)
    assert estimate.fits and estimate.warning(vehicles, control_rate_hz, speed) is None


@pytest.mark.parametrize(
    "vehicles, control_rate_hz, speed",
    [(13, 20.0, 1.5), (13, 20.0, 2.0), (19, 20.0, 1.0), (34, 5.0, 1.0), (43, 5.0, 1.0), (208, 5.0, 1.0)],
)
def test_runs_that_fell_behind_on_two_cores_are_warned(vehicles: int, control_rate_hz: float, speed: float) -> None:
    warning = estimate_capacity(vehicles, control_rate_hz, speed, available_cores=2).warning(vehicles, control_rate_hz, speed)
    assert warning is not None and f"{vehicles} agents" in warning and "\n" not in warning


def test_more_cores_hold_more_agents() -> None:
    assert not estimate_capacity(208, 5.0, 1.0, available_cores=2).fits
    assert estimate_capacity(208, 5.0, 1.0, available_cores=16).fits
    assert estimate_capacity(13, 20.0, 1.0, 2).needed_cores < estimate_capacity(13, 20.0, 2.0, 2).needed_cores


def test_agents_together_weigh_about_four_simulator_processes_whatever_their_number() -> None:
    from gcs.processes.host_capacity import AGENT_MIN_NICENESS, NICE_WEIGHTS, agent_niceness

    assert agent_niceness(13) == 5, "the paper's fleet keeps the nice it always had"
    assert agent_niceness(1) == AGENT_MIN_NICENESS, "a small fleet still runs below the simulator"
    for fleet_size in (13, 19, 34, 100, 208):
        weight = fleet_size * NICE_WEIGHTS[agent_niceness(fleet_size)]
        assert 2.5 * 1024 <= weight <= 6 * 1024, (fleet_size, weight)
    assert agent_niceness(10_000) == 19
