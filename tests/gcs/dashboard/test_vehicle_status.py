"""A vehicle's public status: link state from heartbeat age, position and footprint in WGS84."""

from __future__ import annotations

import math

import numpy as np

from comms.frames import GeodeticHome, geodetic_to_enu
from comms.gcs_status import LinkState
from comms.messages import FLAG_FAILSAFE, NeighbourState
from gcs.dashboard.vehicle_status import LinkView, footprint_en_m, link_state, vehicle_status

HOME = GeodeticHome(lat_deg=47.0, lon_deg=8.0, alt_m=400.0)


def test_link_state_goes_stale_at_half_the_bound_and_lost_past_it() -> None:
    assert link_state(0.3, 2.0) is LinkState.OK
    assert link_state(1.5, 2.0) is LinkState.STALE
    assert link_state(2.5, 2.0) is LinkState.LOST
    assert link_state(math.inf, 2.0) is LinkState.LOST


def test_footprint_side_is_two_h_tan_half_fov() -> None:
    square = footprint_en_m((10.0, 20.0), 10.0, 90.0)
    assert np.allclose(square.min(axis=0), [0.0, 10.0]) and np.allclose(square.max(axis=0), [20.0, 30.0])


def test_status_places_the_vehicle_and_its_footprint_in_wgs84_with_the_georeference_offset() -> None:
    state = NeighbourState(sender_id=3, role="boundary", seq=1, t_s=5.0, position_en_m=(30.0, -40.0), altitude_m=10.0,
                           velocity_en_mps=(1.0, 2.0), flags=FLAG_FAILSAFE, battery_fraction=0.8)
    status = vehicle_status(3, "boundary", "A", LinkView(flight_mode="OFFBOARD", armed=True, heartbeat_age_s=0.1), state,
                            agent_alive=True, lost_after_s=2.0, state_age_s=0.05, offset_en_m=(1.0, 1.0), home=HOME,
                            fov_deg=60.0)
    assert status.failsafe and status.link is LinkState.OK and status.battery_fraction == 0.8
    enu = geodetic_to_enu(status.lat_deg, status.lon_deg, HOME.alt_m, HOME)
    assert np.allclose(np.asarray(enu).reshape(-1)[:2], [31.0, -39.0], atol=1e-3)
    corners = np.array([geodetic_to_enu(lat, lon, HOME.alt_m, HOME)[:2] for lon, lat in status.footprint_lonlat])
    side = 2 * 10.0 * math.tan(math.radians(30.0))
    assert np.allclose(corners.max(axis=0) - corners.min(axis=0), [side, side], atol=1e-3)


def test_a_vehicle_never_heard_has_no_position_and_a_lost_link() -> None:
    status = vehicle_status(9, "follower", "", LinkView(), None, agent_alive=False, lost_after_s=2.0,
                            state_age_s=math.inf, offset_en_m=(0.0, 0.0), home=HOME, fov_deg=60.0)
    assert status.lat_deg is None and status.link is LinkState.LOST and status.heartbeat_age_s is None
