"""A lightweight PX4-style mock autopilot fleet: simulated vehicles that MAVSDK, QGroundControl and pymavlink treat as PX4."""
