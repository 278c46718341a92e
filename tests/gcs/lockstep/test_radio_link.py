"""The lockstep radio carries the wire format: encoded once, decoded once, delivered by range, loss and latency."""

import numpy as np

from comms.messages import NeighbourState
from comms.radio_model import RadioModel
from gcs.lockstep.radio_link import InMemoryRadio


def _msg(vid: int, x: float, seq: int = 1, t_s: float = 0.0, ring_radius_m: float | None = None) -> NeighbourState:
    extras = {} if ring_radius_m is None else {"ring_radius_m": ring_radius_m}
    return NeighbourState(sender_id=vid, role="boundary", seq=seq, t_s=t_s, position_en_m=(x, 0.0), altitude_m=10.0,
                          extras=extras)


def _positions(*xs: float) -> np.ndarray:
    return np.array([[x, 0.0, 10.0] for x in xs])


def _senders(inbox) -> list[int]:
    return sorted(m.sender_id for m in inbox.states)


def test_range_gates_who_hears_whom() -> None:
    radio = InMemoryRadio(RadioModel(range_m=25.0), [1, 2, 3])
    radio.broadcast(0.0, _positions(0.0, 20.0, 50.0), [_msg(1, 0.0), _msg(2, 20.0), _msg(3, 50.0)])
    inboxes = radio.deliver(0.05)
    assert [_senders(i) for i in inboxes] == [[2], [1], []]


def test_what_only_the_wire_carries_arrives_and_one_decoded_message_is_shared() -> None:
    radio = InMemoryRadio(RadioModel(range_m=25.0), [1, 2, 3])
    decoded = radio.broadcast(0.0, _positions(0.0, 5.0, 10.0), [_msg(1, 0.0, ring_radius_m=14.5), None, None])
    assert decoded[0] is not None and decoded[0].extras == {"ring_radius_m": 14.5} and decoded[1:] == [None, None]
    inboxes = radio.deliver(0.0)
    assert inboxes[1].states[0] is inboxes[2].states[0] is decoded[0]
    assert radio.bytes_sent > 0 and radio.stats.dropped_total() == 0


def test_latency_delays_delivery() -> None:
    radio = InMemoryRadio(RadioModel(range_m=25.0, latency_s=0.25), [1, 2])
    radio.broadcast(0.0, _positions(0.0, 5.0), [_msg(1, 0.0), _msg(2, 5.0)])
    assert [_senders(i) for i in radio.deliver(0.1)] == [[], []]
    assert [_senders(i) for i in radio.deliver(0.3)] == [[2], [1]]
    assert [_senders(i) for i in radio.deliver(0.4)] == [[], []]


def test_loss_is_deterministic_for_a_seed() -> None:
    def run(seed: int) -> list[int]:
        radio = InMemoryRadio(RadioModel(range_m=25.0, loss_probability=0.5, seed=seed), [1, 2])
        out = []
        for k in range(50):
            radio.broadcast(0.1 * k, _positions(0.0, 5.0), [_msg(1, 0.0, seq=k + 1), _msg(2, 5.0, seq=k + 1)])
            out.append(len(radio.deliver(0.1 * k)[0].states))
        return out

    assert run(3) == run(3)
    assert run(3) != run(4)
    assert 10 < sum(run(3)) < 40
