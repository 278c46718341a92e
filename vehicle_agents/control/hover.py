"""Where a drone waits in OFFBOARD before its mission starts: over its pad, at its take-off altitude (pure).

A zero velocity setpoint only holds the velocity: in wind, every gust the velocity loop has not yet rejected moves
the drone, and nothing brings it back, so two drones from pads 1.5 m apart could drift together while they wait
(`circle` under `moderate` as processes: 0.97 m). Hover is therefore a position hold on the point the drone took
off to, as PX4's Hold would fly it: a proportional pull, limited in speed.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from vehicle_agents.control.types import OwnState, VelocityCommand

HOVER_GAIN_PER_S = 1.0
"""Pull towards the hover point [1/s] (PX4's MPC_XY_P and MPC_Z_P default to 0.95 and 1.0)."""
HOVER_MAX_SPEED_MPS = 1.0
"""At most this fast back to the hover point [m/s]: a drone far from it (a long take-off drift) returns gently."""


def hover_velocity(own: OwnState, pad_en_m: Sequence[float], altitude_m: float) -> VelocityCommand:
    """The velocity [m/s; E, N, U] that holds the drone over its pad at ``altitude_m``."""
    error = np.array([pad_en_m[0] - own.position_en_m[0], pad_en_m[1] - own.position_en_m[1],
                      altitude_m - own.altitude_m], dtype=float) * HOVER_GAIN_PER_S
    speed = float(np.linalg.norm(error))
    if speed > HOVER_MAX_SPEED_MPS:
        error *= HOVER_MAX_SPEED_MPS / speed
    return VelocityCommand(error)
