"""A paced fleet skips setpoints re-sent while its clock stands still, and takes them again once it moves."""

from __future__ import annotations

import socket
import time

from mock_autopilot.fleet import Fleet
from mock_autopilot.ports import onboard_port
from tests.mock_autopilot.test_repeated_setpoint import _setpoint


def _wait_for(predicate, timeout_s: float = 5.0) -> bool:  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.02)
    return predicate()


def test_resends_at_a_standing_clock_are_skipped_and_taken_once_it_moves() -> None:
    base = 28700
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        sock.bind(("127.0.0.1", onboard_port(base, 0, base + 90)))
        with Fleet(1, base_port=base, gcs_port=base + 90, initial_gate_s=0.5) as fleet:
            assert _wait_for(lambda: fleet.last_tick_t_s >= 0.5)
            vehicle, link = fleet.vehicles[0], fleet.links[0]["onboard"]
            target = link.local_address
            for seq in range(10):
                sock.sendto(_setpoint(seq, 1000 + 50 * seq), target)
            assert _wait_for(lambda: link.received_datagrams >= 10)
            assert _wait_for(lambda: link.repeated_setpoints.skipped == 8)
            assert vehicle.setpoint_t_s == 0.5
            assert vehicle.offboard_setpoint is not None
            fleet.set_gate(0.6)
            assert _wait_for(lambda: fleet.last_tick_t_s >= 0.6)
            sock.sendto(_setpoint(10, 1500), target)
            assert _wait_for(lambda: vehicle.setpoint_t_s == 0.6)
            sock.sendto(_setpoint(11, 1550, vx=2.0), target)
            assert _wait_for(lambda: link.received_datagrams >= 12)
            time.sleep(0.1)
            assert link.repeated_setpoints.skipped == 8
