import numpy as np

from mission_plan.roster import RosterEntry
from vehicle_agents.control.launch_stand_ins import launch_stand_ins
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.step import control_step, initial_memory
from vehicle_agents.control.types import NeighbourInfo, OwnState

ROSTER = (
    RosterEntry(1, "follower", layer=1, ref_id=3, pad_en_m=(0.0, 0.0)),
    RosterEntry(2, "follower", layer=1, ref_id=3, pad_en_m=(1.2, 0.0)),
    RosterEntry(3, "boundary", "A", 0, pad_en_m=(0.0, -5.0)),
    RosterEntry(4, "leader", has_gps=True),
)
PARAMS = ControlParams(mode="improved", roster=ROSTER)


def test_unheard_vehicles_with_pads_stand_in_at_rest_on_them() -> None:
    boundary = NeighbourInfo(3, "boundary", np.array([0.0, -5.0]), np.zeros(2), 10.0, group="A")
    stand_ins = launch_stand_ins(PARAMS, own_id=1, heard=[boundary], elapsed_s=0.4)
    assert [n.vehicle_id for n in stand_ins] == [2]
    assert np.allclose(stand_ins[0].position_en_m, (1.2, 0.0))
    assert np.allclose(stand_ins[0].velocity_en_mps, 0.0)
    assert stand_ins[0].role == "follower" and stand_ins[0].age_s == 0.4


def test_the_plan_stands_in_no_longer_than_the_table_keeps_a_silent_neighbour() -> None:
    assert launch_stand_ins(PARAMS, 1, [], PARAMS.neighbour_timeout_s)
    assert launch_stand_ins(PARAMS, 1, [], PARAMS.neighbour_timeout_s + 0.05) == []


def _east_command(neighbours: list[NeighbourInfo], elapsed_s: float) -> float:
    """Follower 1 on its pad, told by its law to fly east at full speed towards follower 2's pad 1.2 m away."""
    own = OwnState(position_en_m=np.zeros(2), altitude_m=10.0)
    memory = initial_memory("follower", 1, PARAMS)
    # The leader far to the east: the follower flocks round it, so its law commands eastward flight.
    leader = NeighbourInfo(4, "leader", np.array([40.0, 0.0]), np.zeros(2), 10.0)
    command, _ = control_step("follower", memory, own, None, [leader, *neighbours], PARAMS, elapsed_s)
    return float(command.velocity_enu_mps[0])


def test_an_unheard_neighbour_on_its_pad_holds_the_barrier_at_launch() -> None:
    unbarred = _east_command([], PARAMS.neighbour_timeout_s + 1.0)
    barred = _east_command([], 0.1)
    assert unbarred > 1.0
    assert barred < 0.5 * unbarred


def test_once_heard_the_neighbour_itself_replaces_its_pad() -> None:
    away = NeighbourInfo(2, "follower", np.array([0.0, 30.0]), np.zeros(2), 10.0)
    assert _east_command([away], 0.1) == _east_command([], PARAMS.neighbour_timeout_s + 1.0)
