"""The onboard software of one drone: perception, the control law of its role, and the MAVLink/Zenoh adapters."""
