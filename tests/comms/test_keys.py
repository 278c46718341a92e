"""Key expressions: the public names are exactly the documented ones; parsing is strict."""

from __future__ import annotations

import pytest

from comms.keys import KeyNameError, MissionKeys


def test_public_keys_are_the_documented_ones() -> None:
    k = MissionKeys("circle")
    assert k.state(7) == "floodwatch/circle/uav/7/state"
    assert k.polygon == "floodwatch/circle/gcs/polygon"
    assert k.alive(7) == "floodwatch/circle/alive/7"
    assert k.alive("gcs") == "floodwatch/circle/alive/gcs"
    assert k.all_states == "floodwatch/circle/uav/*/state"
    assert k.all_alive == "floodwatch/circle/alive/*"


def test_internal_keys_are_under_the_mission() -> None:
    k = MissionKeys("m-1")
    for key in (k.truth, k.camera(3), k.inbox(3), k.radio_stats, k.edge(3), k.command, k.events):
        assert key.startswith("floodwatch/m-1/") and "*" not in key


@pytest.mark.parametrize("name", ["", "a/b", "a*", "$x", "a b", "x" * 65, "a?b", "a#b"])
def test_bad_mission_names_rejected(name: str) -> None:
    with pytest.raises(KeyNameError):
        MissionKeys(name)


def test_vehicle_id_parsing() -> None:
    k = MissionKeys("m")
    assert k.vehicle_id_of(k.state(12)) == 12
    assert k.vehicle_id_of(k.alive(3)) == 3
    assert k.vehicle_id_of(k.inbox(5)) == 5
    assert k.vehicle_id_of(k.camera(9)) == 9
    assert k.vehicle_id_of(k.alive("gcs")) is None
    assert k.vehicle_id_of("floodwatch/other/uav/1/state") is None
    assert k.vehicle_id_of("floodwatch/m/uav/-1/state") is None
    assert k.vehicle_id_of("floodwatch/m/uav/99999999999/state") is None
    assert k.vehicle_id_of("floodwatch/m") is None
    assert k.participant_of(k.alive("radio")) == "radio"
    assert k.participant_of("floodwatch/x/alive/1") is None
