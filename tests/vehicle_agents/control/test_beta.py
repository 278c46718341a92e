import numpy as np

from vehicle_agents.control.beta import beta, separation_velocity


def test_beta_falls_from_one_to_zero_smoothly() -> None:
    d = 10.0
    assert beta(0.0, d) == 1.0
    assert abs(float(beta(5.0, d)) - 0.5) < 1e-12
    assert float(beta(10.0, d)) == 0.0
    assert float(beta(25.0, d)) == 0.0
    x = np.linspace(0.0, d, 201)
    values = beta(x, d)
    assert np.all(np.diff(values) <= 1e-12)
    assert np.all((values >= 0.0) & (values <= 1.0))
    # zero slope at both ends (the 7th-order smooth step of eq 7)
    assert abs(float(beta(0.01, d)) - 1.0) < 1e-6
    assert float(beta(9.99, d)) < 1e-6


def test_separation_pushes_away_and_vanishes_beyond_d() -> None:
    own = np.array([0.0, 0.0])
    v = separation_velocity(own, np.array([[3.0, 0.0]]), 10.0, 1.0)
    assert v[0] < 0.0 and abs(v[1]) < 1e-12
    assert np.allclose(separation_velocity(own, np.array([[10.5, 0.0]]), 10.0, 1.0), 0.0)
    both = separation_velocity(own, np.array([[3.0, 0.0], [-3.0, 0.0]]), 10.0, 1.0)
    assert np.allclose(both, 0.0)
    assert np.allclose(separation_velocity(own, np.zeros((0, 2)), 10.0, 1.0), 0.0)
    # the push at distance x is gain * beta(x)
    assert abs(np.linalg.norm(separation_velocity(own, np.array([[0.0, 5.0]]), 10.0, 2.0)) - 1.0) < 1e-12
