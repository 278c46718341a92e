"""What N autopilots report, as arrays: the core's view of the vehicles (local NED from each pad, PX4 mode names).

An agent builds a batch of one from its MAVLink link's newest telemetry; the lockstep engine builds one for the
whole fleet from its vehicle backend. ``link_silence_s`` is how long each autopilot has been silent (wall seconds
in an agent: link health is a wall-clock matter; 0 in lockstep, where the backend always answers); NaN = never heard.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from vehicle_agents.autopilot_link import AutopilotTelemetry


@dataclass(frozen=True)
class TelemetryBatch:
    """Newest telemetry of N vehicles; row i is vehicle i of the plan."""

    position_ned_m: NDArray[np.float64]
    """(N, 3) [m; local NED from the pad]."""
    velocity_ned_mps: NDArray[np.float64]
    """(N, 3) [m/s; NED]."""
    yaw_ned_rad: NDArray[np.float64]
    armed: NDArray[np.bool_]
    in_air: NDArray[np.bool_]
    flight_mode: tuple[str, ...]
    """PX4 mode names as MAVSDK spells them (OFFBOARD, HOLD, TAKEOFF, LAND, ...)."""
    battery_fraction: NDArray[np.float64]
    ready_to_arm: NDArray[np.bool_]
    has_global_position: NDArray[np.bool_]
    latitude_deg: NDArray[np.float64]
    longitude_deg: NDArray[np.float64]
    link_silence_s: NDArray[np.float64]
    """Seconds since each autopilot's newest message; NaN before the first."""

    def __len__(self) -> int:
        return len(self.flight_mode)

    def heard(self, index: int) -> bool:
        """Has vehicle ``index``'s autopilot ever spoken?"""
        return not math.isnan(float(self.link_silence_s[index]))

    def vehicle(self, index: int) -> AutopilotTelemetry:
        """Row ``index`` as the one-vehicle value the flight phase and the state message read (link health is
        ``link_silence_s``, so the wall-clock stamp is left unset)."""
        p, v = self.position_ned_m[index], self.velocity_ned_mps[index]
        return AutopilotTelemetry(
            position_ned_m=(float(p[0]), float(p[1]), float(p[2])),
            velocity_ned_mps=(float(v[0]), float(v[1]), float(v[2])),
            yaw_ned_rad=float(self.yaw_ned_rad[index]),
            armed=bool(self.armed[index]),
            in_air=bool(self.in_air[index]),
            flight_mode=self.flight_mode[index],
            battery_fraction=float(self.battery_fraction[index]),
            ready_to_arm=bool(self.ready_to_arm[index]),
            has_global_position=bool(self.has_global_position[index]),
            latitude_deg=float(self.latitude_deg[index]),
            longitude_deg=float(self.longitude_deg[index]),
        )


def telemetry_batch(telemetry: Sequence[AutopilotTelemetry], now_monotonic_s: float) -> TelemetryBatch:
    """A batch from per-vehicle link telemetry (the agent's shell); silence is measured on the wall clock."""
    silence = [math.nan if t.last_message_monotonic_s == 0.0 else max(0.0, now_monotonic_s - t.last_message_monotonic_s)
               for t in telemetry]
    return TelemetryBatch(
        position_ned_m=np.array([t.position_ned_m for t in telemetry], dtype=float).reshape(-1, 3),
        velocity_ned_mps=np.array([t.velocity_ned_mps for t in telemetry], dtype=float).reshape(-1, 3),
        yaw_ned_rad=np.array([t.yaw_ned_rad for t in telemetry], dtype=float),
        armed=np.array([t.armed for t in telemetry], dtype=bool),
        in_air=np.array([t.in_air for t in telemetry], dtype=bool),
        flight_mode=tuple(t.flight_mode for t in telemetry),
        battery_fraction=np.array([t.battery_fraction for t in telemetry], dtype=float),
        ready_to_arm=np.array([t.ready_to_arm for t in telemetry], dtype=bool),
        has_global_position=np.array([t.has_global_position for t in telemetry], dtype=bool),
        latitude_deg=np.array([t.latitude_deg for t in telemetry], dtype=float),
        longitude_deg=np.array([t.longitude_deg for t in telemetry], dtype=float),
        link_silence_s=np.array(silence, dtype=float),
    )
