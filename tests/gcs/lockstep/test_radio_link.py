import numpy as np

from comms.radio_model import RadioModel
from gcs.lockstep.radio_link import RadioLink
from vehicle_agents.control.types import NeighbourInfo


def _msg(vid: int, x: float) -> NeighbourInfo:
    return NeighbourInfo(vid, "boundary", np.array([x, 0.0]), np.zeros(2), 10.0)


def _positions(*xs: float) -> np.ndarray:
    return np.array([[x, 0.0, 10.0] for x in xs])


def test_range_gates_who_hears_whom() -> None:
    link = RadioLink(RadioModel(range_m=25.0), [1, 2, 3], keep_s=5.0)
    link.broadcast(0, 0.0, _positions(0.0, 20.0, 50.0), [_msg(1, 0.0), _msg(2, 20.0), _msg(3, 50.0)])
    link.deliver(0.0)
    assert sorted(n.vehicle_id for n in link.heard_by(0, 0.0)) == [2]
    assert sorted(n.vehicle_id for n in link.heard_by(1, 0.0)) == [1]
    assert link.heard_by(2, 0.0) == []


def test_latency_delays_delivery_and_age_counts_from_the_stamp() -> None:
    link = RadioLink(RadioModel(range_m=25.0, latency_s=0.25), [1, 2], keep_s=5.0)
    link.broadcast(0, 0.0, _positions(0.0, 5.0), [_msg(1, 0.0), _msg(2, 5.0)])
    link.deliver(0.1)
    assert link.heard_by(0, 0.1) == []
    link.deliver(0.3)
    heard = link.heard_by(0, 0.3)
    assert len(heard) == 1 and abs(heard[0].age_s - 0.3) < 1e-12


def test_newest_message_wins_and_silent_vehicles_send_nothing() -> None:
    link = RadioLink(RadioModel(range_m=25.0), [1, 2], keep_s=5.0)
    link.broadcast(0, 0.0, _positions(0.0, 5.0), [_msg(1, 0.0), _msg(2, 5.0)])
    link.broadcast(1, 0.1, _positions(0.0, 6.0), [_msg(1, 0.0), _msg(2, 6.0)])
    link.deliver(0.1)
    heard = link.heard_by(0, 0.1)
    assert heard[0].position_en_m[0] == 6.0
    link.broadcast(2, 0.2, _positions(0.0, 7.0), [_msg(1, 0.0), None])
    link.deliver(0.2)
    assert link.heard_by(0, 0.2)[0].position_en_m[0] == 6.0


def test_loss_is_deterministic_for_a_seed() -> None:
    def run(seed: int) -> list[int]:
        link = RadioLink(RadioModel(range_m=25.0, loss_probability=0.5, seed=seed), [1, 2], keep_s=0.05)
        out = []
        for k in range(50):
            link.broadcast(k, 0.1 * k, _positions(0.0, 5.0), [_msg(1, 0.0), _msg(2, 5.0)])
            link.deliver(0.1 * k)
            out.append(len(link.heard_by(0, 0.1 * k)))
        return out

    assert run(3) == run(3)
    assert run(3) != run(4)
    assert 10 < sum(run(3)) < 40
