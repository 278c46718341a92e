import numpy as np

from vehicle_agents.control.encircle import heard_encircled, is_leading, meets_other_leader
from vehicle_agents.control.params import ControlParams, RosterEntry
from vehicle_agents.control.types import NeighbourInfo

ROSTER = (RosterEntry(1, "boundary", "A", 0), RosterEntry(2, "boundary", "A", 1), RosterEntry(3, "boundary", "B", 0))
PARAMS = ControlParams(roster=ROSTER, meet_distance_m=10.0, min_encircle_travel_m=8.0)


def _nb(vid: int, group: str, pos: tuple[float, float], leading: bool = False, encircled: bool = False) -> NeighbourInfo:
    return NeighbourInfo(vid, "boundary", np.array(pos), np.zeros(2), 10.0, group=group, leading=leading, encircled=encircled)


def test_leading_is_lowest_rank_heard() -> None:
    assert is_leading(ROSTER[0], [_nb(2, "A", (0, 0))], PARAMS)
    assert not is_leading(ROSTER[1], [_nb(1, "A", (0, 0))], PARAMS)
    assert is_leading(ROSTER[1], [_nb(3, "B", (0, 0))], PARAMS)  # A's leader lost: rank 1 takes over


def test_meeting_needs_the_other_leader_close_ahead_after_travelling() -> None:
    own = np.array([0.0, 0.0])
    north = np.array([0.0, 1.0])
    ahead = [_nb(3, "B", (0.0, 6.0), leading=True)]
    behind = [_nb(3, "B", (0.0, -6.0), leading=True)]
    far = [_nb(3, "B", (0.0, 16.0), leading=True)]
    not_leading = [_nb(3, "B", (0.0, 6.0), leading=False)]
    assert meets_other_leader(ROSTER[0], own, north, ahead, 30.0, PARAMS)
    assert not meets_other_leader(ROSTER[0], own, north, ahead, 2.0, PARAMS)  # still at the launch site
    assert not meets_other_leader(ROSTER[0], own, north, behind, 30.0, PARAMS)
    assert not meets_other_leader(ROSTER[0], own, north, far, 30.0, PARAMS)
    # no flag, but B's lowest rank heard: still B's leading drone
    assert meets_other_leader(ROSTER[0], own, north, not_leading, 30.0, PARAMS)
    roster = (*ROSTER, RosterEntry(4, "boundary", "B", 1))
    params = ControlParams(roster=roster, meet_distance_m=10.0, min_encircle_travel_m=8.0)
    b_follower_close = [_nb(4, "B", (0.0, 6.0)), _nb(3, "B", (0.0, 30.0))]
    assert not meets_other_leader(roster[0], own, north, b_follower_close, 30.0, params)
    assert not meets_other_leader(ROSTER[0], own, north, [_nb(2, "A", (0.0, 6.0), leading=True)], 30.0, PARAMS)


def test_encircled_news_spreads_by_radio() -> None:
    assert heard_encircled([_nb(2, "A", (0, 0), encircled=True)])
    assert not heard_encircled([_nb(2, "A", (0, 0))])
