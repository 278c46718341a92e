"""Conversions between autopilot telemetry, radio messages and the control law's inputs."""

from __future__ import annotations

import numpy as np
import pytest

from comms.messages import FLAG_HAS_GPS, FLAG_LEADING, FLAG_LEAVING, FLAG_OFFBOARD, NeighbourState, decode, encode
from vehicle_agents.autopilot_link import AutopilotTelemetry
from vehicle_agents.control.types import NeighbourInfo, VelocityCommand
from vehicle_agents.core.neighbours import Inbox, heard_after
from vehicle_agents.onboard_view import neighbour_info, own_state, state_message, velocity_ned


def test_own_state_is_pad_plus_local_ned_in_enu() -> None:
    tel = AutopilotTelemetry(position_ned_m=(2.0, 1.0, -10.0), velocity_ned_mps=(0.5, -0.25, -1.0))
    own = own_state(tel, (14.0, 1.5), has_gps=False)
    np.testing.assert_allclose(own.position_en_m, [15.0, 3.5])
    assert own.altitude_m == pytest.approx(10.0)
    np.testing.assert_allclose(own.velocity_en_mps, [-0.25, 0.5])


def test_velocity_ned_swaps_axes_and_drops_nan() -> None:
    assert velocity_ned(VelocityCommand(np.array([1.0, 2.0, 0.5]))) == (2.0, 1.0, -0.5)
    assert velocity_ned(VelocityCommand(np.array([np.nan, 2.0, 0.0]))) == (2.0, 0.0, -0.0)


def _msg(sender: int, t_s: float, flags: int = 0) -> NeighbourState:
    return NeighbourState(sender_id=sender, role="boundary", seq=1, t_s=t_s, position_en_m=(1.0, 2.0), altitude_m=10.0,
                          group="A", flags=flags, extras={"ring_radius_m": 14.0})


def _infos(msgs: list[NeighbourState], now_s: float, own_id: int, departed: set[int],
           timeout_s: float) -> list[NeighbourInfo]:
    heard, _ = heard_after({}, frozenset(departed), Inbox(states=msgs), own_id, now_s, timeout_s)
    return [neighbour_info(msg, now_s - msg.t_s) for msg in heard.values()]


def test_neighbour_infos_filter_self_departed_leaving_and_stale() -> None:
    msgs = [_msg(1, 9.5), _msg(2, 9.9), _msg(3, 5.0), _msg(4, 9.9, FLAG_LEAVING), _msg(5, 9.9)]
    infos = _infos(msgs, now_s=10.0, own_id=1, departed={5}, timeout_s=3.0)
    assert [n.vehicle_id for n in infos] == [2]
    assert infos[0].age_s == pytest.approx(0.1)
    assert infos[0].group == "A" and infos[0].ring_radius_m == 14.0


def test_state_message_round_trips_with_absolute_edge_points() -> None:
    tel = AutopilotTelemetry(position_ned_m=(0.0, 0.0, -10.0), flight_mode="OFFBOARD", armed=True, in_air=True,
                             has_global_position=True, latitude_deg=47.0, longitude_deg=8.0)
    own = own_state(tel, (14.0, 0.0), has_gps=True)
    edge = np.column_stack([np.linspace(13.0, 15.0, 100), np.zeros(100)])
    broadcast = NeighbourInfo(vehicle_id=3, role="boundary", position_en_m=own.position_en_m,
                              velocity_en_mps=own.velocity_en_mps, altitude_m=10.0, group="B", leading=True,
                              encircled=False, ring_radius_m=13.0)
    msg = state_message(seq=7, t_s=12.5, broadcast=broadcast, own=own, tel=tel, perception=None,
                        edge_points_en_m=edge, leaving=False, low_battery=False)
    back = decode(NeighbourState, encode(msg))
    assert back is not None and back.sender_id == 3 and back.group == "B"
    assert back.has(FLAG_OFFBOARD) and back.has(FLAG_HAS_GPS) and back.has(FLAG_LEADING) and back.lat_deg == 47.0
    assert back.extras == {"ring_radius_m": 13.0}
    pts = np.array(back.edge_points_en_m)
    assert 3 <= len(pts) <= 32
    assert pts[:, 0].min() == pytest.approx(13.0) and pts[:, 0].max() == pytest.approx(15.0)
    info = _infos([back], now_s=12.6, own_id=1, departed=set(), timeout_s=3.0)[0]
    assert info.leading and info.group == "B" and info.ring_radius_m == 13.0
