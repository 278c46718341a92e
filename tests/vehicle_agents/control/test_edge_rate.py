import numpy as np

from vehicle_agents.control.edge_rate import EdgeRateState, feedforward, update_edge_rate


def test_filtered_rate_converges_to_edge_velocity() -> None:
    state = EdgeRateState()
    velocity = np.array([0.3, -0.1])
    for k in range(100):
        t = 0.1 * k
        state = update_edge_rate(state, np.array([1.0, 2.0]) + velocity * t, t, 1.0)
    assert np.allclose(state.rate_en_mps, velocity, atol=1e-3)


def test_losing_the_edge_resets_the_estimate() -> None:
    state = update_edge_rate(EdgeRateState(), np.array([0.0, 0.0]), 0.0, 1.0)
    state = update_edge_rate(state, None, 0.1, 1.0)
    assert state.p_en_m is None and state.rate_en_mps is None


def test_readings_of_the_feedforward() -> None:
    rate = np.array([1.0, 0.2])
    normal = np.array([0.0, 1.0])
    assert np.allclose(feedforward(rate, normal, "full"), rate)
    assert np.allclose(feedforward(rate, normal, "normal"), [0.0, 0.2])
    assert np.allclose(feedforward(rate, normal, "none"), 0.0)
    assert np.allclose(feedforward(None, normal, "full"), 0.0)
