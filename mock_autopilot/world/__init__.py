"""The simulated world the drones watch: flood models and the downward camera. Simulation-only."""
