import math

import numpy as np

from comms.frames import (
    GeodeticHome,
    enu_to_geodetic,
    enu_to_ned,
    geodetic_to_enu,
    local_ned_to_mission_enu,
    mission_enu_to_local_ned,
    ned_to_enu,
    yaw_enu_to_ned_rad,
    yaw_ned_to_enu_rad,
)


def test_enu_ned_swap_is_an_involution() -> None:
    v = np.array([[1.0, 2.0, 3.0], [-4.0, 5.0, -6.0]])
    assert np.allclose(enu_to_ned(v), [[2.0, 1.0, -3.0], [5.0, -4.0, 6.0]])
    assert np.allclose(ned_to_enu(enu_to_ned(v)), v)


def test_local_ned_and_mission_enu_round_trip_through_a_pad() -> None:
    pad = np.array([14.0, 1.5, 0.0])
    local = np.array([2.0, -3.0, -10.0])  # 2 m north, 3 m west, 10 m up
    mission = local_ned_to_mission_enu(local, pad)
    assert np.allclose(mission, [11.0, 3.5, 10.0])
    assert np.allclose(mission_enu_to_local_ned(mission, pad), local)


def test_geodetic_round_trip_and_scale() -> None:
    home = GeodeticHome()
    enu = np.array([[100.0, 0.0, 5.0], [0.0, 100.0, 0.0], [-30.0, 42.0, 1.0], [0.0, 0.0, 0.0]])
    geo = enu_to_geodetic(enu, home)
    back = geodetic_to_enu(geo[:, 0], geo[:, 1], geo[:, 2], home)
    assert np.allclose(back, enu, atol=1e-6)
    # 100 m north is 100 / (R * pi / 180) degrees of latitude
    assert math.isclose(geo[1, 0] - home.lat_deg, 100.0 / (6_371_000.0 * math.pi / 180.0), rel_tol=1e-6)
    assert math.isclose(geo[0, 2], home.alt_m + 5.0)


def test_yaw_conversions() -> None:
    assert math.isclose(yaw_ned_to_enu_rad(0.0), math.pi / 2)  # facing north
    assert math.isclose(yaw_ned_to_enu_rad(math.pi / 2), 0.0, abs_tol=1e-12)  # facing east
    for h in np.linspace(-3.0, 3.0, 7):
        assert math.isclose(math.remainder(yaw_ned_to_enu_rad(yaw_enu_to_ned_rad(h)) - h, 2 * math.pi), 0.0, abs_tol=1e-12)


def test_the_scalar_swap_agrees_with_the_array_conversions() -> None:
    from comms.frames import enu_to_ned, ned_to_enu, swap_ned_enu

    v = (1.5, -2.0, 3.25)
    assert swap_ned_enu(*v) == tuple(ned_to_enu(v)) == tuple(enu_to_ned(v))
    assert swap_ned_enu(*swap_ned_enu(*v)) == v
