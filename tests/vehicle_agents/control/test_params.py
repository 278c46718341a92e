import pytest

from vehicle_agents.control.params import (
    PAPER_PIXEL_GAINS,
    ControlParams,
    ControlParamsError,
    RosterEntry,
    params_for_mode,
)


def test_modes_and_presets() -> None:
    paper = params_for_mode("paper", {"encircle_speed_mps": 1.0}, ())
    improved = params_for_mode("improved", {"encircle_speed_mps": 1.0, "improved": {"encircle_speed_mps": 3.0}}, ())
    assert paper.encircle_speed_mps == 1.0 and improved.encircle_speed_mps == 3.0
    assert improved.edge_point_tracking and not paper.edge_point_tracking
    preset = params_for_mode("paper", {"gain_preset": "paper_pixels"}, ())
    assert preset.k_boundary_per_s == PAPER_PIXEL_GAINS


@pytest.mark.parametrize(
    "table, field",
    [
        ({"separation_distance_m": -1.0}, "control.separation_distance_m"),
        ({"no_such_gain": 1.0}, "control.no_such_gain"),
        ({"pdot_reading": "sideways"}, "control.pdot_reading"),
        ({"gain_preset": "kilometres"}, "control.gain_preset"),
        ({"encircle_speed_mps": "fast"}, "control.encircle_speed_mps"),
    ],
)
def test_bad_values_name_the_field(table: dict, field: str) -> None:
    with pytest.raises(ControlParamsError, match=field):
        params_for_mode("paper", table, ())


def test_unknown_mode() -> None:
    with pytest.raises(ControlParamsError, match="mode"):
        ControlParams(mode="magic")


def test_roster_lookups_are_computed_once_and_stay_out_of_equality() -> None:
    roster = (RosterEntry(vehicle_id=1, role="boundary", group="A", rank=0),
              RosterEntry(vehicle_id=2, role="boundary", group="A", rank=1),
              RosterEntry(vehicle_id=3, role="boundary", group="B", rank=0),
              RosterEntry(vehicle_id=4, role="follower", layer=1))
    params = ControlParams(roster=roster)
    assert params.ring_order() == (3, 2, 1)
    assert params.ring_order() is params.ring_order()
    assert params.rank_of == {1: 0, 2: 1, 3: 0, 4: 0}
    assert [e.vehicle_id for e in params.followers()] == [4]
    assert params == ControlParams(roster=roster)
