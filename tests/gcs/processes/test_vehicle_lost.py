"""When the ground station calls a vehicle lost: two heartbeat periods, which the simulation speed stretches."""

from gcs.processes.fleet_readiness import VEHICLE_LOST_AFTER_S, vehicle_lost_after_s


def test_two_seconds_at_or_above_real_time_and_stretched_below_it() -> None:
    assert vehicle_lost_after_s(1.0) == vehicle_lost_after_s(3.0) == VEHICLE_LOST_AFTER_S == 2.0
    assert vehicle_lost_after_s(0.5) == 4.0
