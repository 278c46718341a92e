"""A vehicle lost to GCS-link silence counts again when its heartbeat returns; one whose agent is gone does not."""

from gcs.processes.lost_vehicles import LostVehicles


def test_link_silence_ends_when_the_heartbeat_returns() -> None:
    losses = LostVehicles()
    losses.link_silent(193, 7.8)
    losses.link_silent(193, 9.0)
    assert losses.since_flood_s == {193: 7.8}
    assert losses.link_back(193)
    assert losses.since_flood_s == {}
    assert not losses.link_back(193)


def test_an_agent_gone_is_lost_for_good() -> None:
    losses = LostVehicles()
    losses.link_silent(5, 3.0)
    losses.agent_gone(5, 4.0)
    losses.agent_gone(6, 4.5)
    assert not losses.link_back(5) and not losses.link_back(6)
    assert losses.since_flood_s == {5: 3.0, 6: 4.5}
