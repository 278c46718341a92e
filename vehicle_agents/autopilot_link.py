"""What the onboard loop needs from an autopilot, as one small interface.

Two implementations exist: :mod:`vehicle_agents.autopilot_link_mavsdk` (the PX4 SDK path, default) and
:mod:`vehicle_agents.autopilot_link_pymavlink` (plain MAVLink). The agent never imports either directly, so it flies
any PX4 (the mock fleet, SITL, hardware) by changing the MAVLink URL only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol


@dataclass(frozen=True)
class AutopilotTelemetry:
    """The newest telemetry from the vehicle; positions in its local NED frame [m], relative to its boot point."""

    position_ned_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    velocity_ned_mps: tuple[float, float, float] = (0.0, 0.0, 0.0)
    yaw_ned_rad: float = 0.0
    roll_rad: float = 0.0
    pitch_rad: float = 0.0
    """Body roll and pitch (ATTITUDE): perception projects the body-fixed camera's pixels through them."""
    armed: bool = False
    in_air: bool = False
    flight_mode: str = "UNKNOWN"
    """PX4 mode name as MAVSDK spells it: READY, TAKEOFF, HOLD, OFFBOARD, LAND, RETURN_TO_LAUNCH, ..."""
    battery_fraction: float = 1.0
    ready_to_arm: bool = False
    has_global_position: bool = False
    latitude_deg: float = float("nan")
    longitude_deg: float = float("nan")
    height_above_ground_m: float = float("nan")
    """The downward rangefinder's reading (DISTANCE_SENSOR) [m]: how far the ground below is, which over relief is not
    the altitude above home; NaN until one is heard (a vehicle without a rangefinder)."""
    last_message_monotonic_s: float = 0.0
    """Wall-clock (``time.monotonic``) time of the newest message from the vehicle: the link-health signal."""


class AutopilotLinkError(RuntimeError):
    """A command the autopilot refused or that timed out; the message says which and why."""


class AutopilotLink(Protocol):
    """Commands and telemetry of one vehicle; every method may raise :class:`AutopilotLinkError`."""

    @property
    def telemetry(self) -> AutopilotTelemetry:
        """The newest telemetry (never blocks)."""
        ...

    async def connect(self, timeout_s: float) -> None:
        """Wait until the autopilot's heartbeat is heard and telemetry flows."""
        ...

    async def arm(self) -> None: ...

    async def takeoff(self, altitude_m: float) -> None:
        """Command AUTO.TAKEOFF to ``altitude_m`` above home and return at once (poll telemetry for progress)."""
        ...

    async def start_offboard(self, velocity_ned_mps: tuple[float, float, float], yaw_ned_rad: float) -> None:
        """Send a first setpoint, then switch to OFFBOARD (PX4 refuses OFFBOARD without a setpoint stream)."""
        ...

    async def set_velocity_ned(self, velocity_ned_mps: tuple[float, float, float], yaw_ned_rad: float) -> None:
        """Replace the streamed velocity setpoint (LOCAL_NED frame, velocity + yaw type_mask)."""
        ...

    async def hold(self) -> None: ...

    async def land(self) -> None: ...

    async def close(self) -> None:
        """Stop streaming and release sockets; never raises."""
        ...
