"""One interface for N simulated vehicles: velocity setpoints and flight-phase requests in, a fleet state out.

In the spirit of Crazyswarm2's ``backend.step(states, actions, dt)``: the lockstep engine owns the clock and calls

1. ``hover_start(altitude_m)`` once: every vehicle hovers ``altitude_m`` above its pad in OFFBOARD with zero
   velocity, and mission time is 0 (SPEC §4: the flood clock starts when all are airborne);
2. each control period ``step(velocity_setpoint_ned_mps, yaw_ned_rad, setpoint_sent, requests, dt_s)``, and reads
   the returned :class:`BackendState` (local NED from each vehicle's pad; the engine converts to mission ENU).

Two implementations: :class:`mock_autopilot.backends.kinematic.KinematicBackend` (the paper's holonomic point with
PX4 limits, vectorised over the fleet) and :class:`mock_autopilot.backends.px4.Px4Backend` (the sans-IO mock PX4,
its MAVLink front end, commander modes and failsafes). Both read the same dynamics: ``KinematicLimits`` and its
``response_time_s``.

Everything here is pure data and checks: no sockets, clocks or threads.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import Protocol, Sequence, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from comms.px4 import MAVSDK_MODE_NAMES



class VehicleRequest(enum.Enum):
    """A flight-phase action for one vehicle this control period, as an offboard application asks PX4 for it.

    The onboard agents' ``vehicle_agents.flight_phase.Action`` maps onto it in the caller (ARM, TAKEOFF,
    START_OFFBOARD, HOLD, LAND; HOVER and FLY are setpoints, not requests), so this package never imports the agents.
    """

    NONE = "none"
    ARM = "arm"
    TAKEOFF = "takeoff"
    START_OFFBOARD = "start_offboard"
    HOLD = "hold"
    LAND = "land"


def read_only(array: NDArray[np.generic]) -> NDArray[np.generic]:
    """``array``, marked read-only: what a :class:`BackendState` holds, so a state stays the value it was."""
    array.flags.writeable = False
    return array


def _optional(values: ArrayLike | None, shape: tuple[int, ...]) -> NDArray[np.float64] | None:
    return None if values is None else read_only(np.array(values, dtype=float).reshape(shape))


@dataclass(frozen=True, eq=False)
class BackendState:
    """Every vehicle at mission time ``t_s`` [s]; rows follow the backend's vehicle order.

    position_ned_m [m; (N,3) local NED from each vehicle's pad], velocity_ned_mps [m/s; (N,3) NED], yaw_ned_rad
    [rad; (N,) clockwise from north], armed / in_air / alive [(N,) bool], flight_mode (N PX4 mode names, the
    values of :class:`comms.px4.Px4Mode`: "OFFBOARD", "POSCTL", "AUTO.LOITER", "AUTO.LAND", ...;
    see :data:`MAVSDK_MODE_NAMES` for MAVSDK's spelling), battery_fraction [(N,) 0..1]. The arrays are read-only;
    equality is identity (arrays have no single truth value).

    Position, velocity and yaw are the truth (what the metrics, the camera and the radio use). What each
    autopilot's estimator reports (what the agents see) is ``estimated_position_ned_m`` / ``estimated_yaw_ned_rad``
    (None: the truth, exact sensors); ``roll_rad`` / ``pitch_rad`` the true tilt (None: level).
    """

    t_s: float
    position_ned_m: NDArray[np.float64]
    velocity_ned_mps: NDArray[np.float64]
    yaw_ned_rad: NDArray[np.float64]
    armed: NDArray[np.bool_]
    in_air: NDArray[np.bool_]
    flight_mode: tuple[str, ...]
    battery_fraction: NDArray[np.float64]
    alive: NDArray[np.bool_]
    estimated_position_ned_m: NDArray[np.float64] | None = None
    estimated_yaw_ned_rad: NDArray[np.float64] | None = None
    roll_rad: NDArray[np.float64] | None = None
    pitch_rad: NDArray[np.float64] | None = None

    @property
    def reported_position_ned_m(self) -> NDArray[np.float64]:
        """The position each autopilot reports [m; (N,3) local NED]: its estimate."""
        return self.position_ned_m if self.estimated_position_ned_m is None else self.estimated_position_ned_m

    @property
    def reported_yaw_ned_rad(self) -> NDArray[np.float64]:
        """The heading each autopilot reports [rad; (N,)]: its estimate."""
        return self.yaw_ned_rad if self.estimated_yaw_ned_rad is None else self.estimated_yaw_ned_rad

    @property
    def tilt_rad(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """True (roll, pitch) [rad; (N,) each], level when the backend models none."""
        zero = np.zeros(self.vehicle_count)
        return (zero if self.roll_rad is None else self.roll_rad, zero if self.pitch_rad is None else self.pitch_rad)

    @classmethod
    def of(
        cls,
        t_s: float,
        position_ned_m: ArrayLike,
        velocity_ned_mps: ArrayLike,
        yaw_ned_rad: ArrayLike,
        armed: ArrayLike,
        in_air: ArrayLike,
        flight_mode: Sequence[str],
        battery_fraction: ArrayLike,
        alive: ArrayLike,
        estimated_position_ned_m: ArrayLike | None = None,
        estimated_yaw_ned_rad: ArrayLike | None = None,
        roll_rad: ArrayLike | None = None,
        pitch_rad: ArrayLike | None = None,
    ) -> BackendState:
        """A state built from copies of the given arrays (so a backend's later steps never change it)."""
        return cls(
            t_s=float(t_s),
            position_ned_m=read_only(np.array(position_ned_m, dtype=float).reshape(-1, 3)),
            velocity_ned_mps=read_only(np.array(velocity_ned_mps, dtype=float).reshape(-1, 3)),
            yaw_ned_rad=read_only(np.array(yaw_ned_rad, dtype=float).reshape(-1)),
            armed=read_only(np.array(armed, dtype=bool).reshape(-1)),
            in_air=read_only(np.array(in_air, dtype=bool).reshape(-1)),
            flight_mode=tuple(flight_mode),
            battery_fraction=read_only(np.array(battery_fraction, dtype=float).reshape(-1)),
            alive=read_only(np.array(alive, dtype=bool).reshape(-1)),
            estimated_position_ned_m=_optional(estimated_position_ned_m, (-1, 3)),
            estimated_yaw_ned_rad=_optional(estimated_yaw_ned_rad, (-1,)),
            roll_rad=_optional(roll_rad, (-1,)),
            pitch_rad=_optional(pitch_rad, (-1,)),
        )

    @property
    def vehicle_count(self) -> int:
        return len(self.flight_mode)


@dataclass(frozen=True, eq=False)
class StepInputs:
    """One control period's inputs after :func:`step_inputs` checked them: (N,3), (N,), (N,) arrays, N requests."""

    velocity_setpoint_ned_mps: NDArray[np.float64]
    yaw_ned_rad: NDArray[np.float64]
    setpoint_sent: NDArray[np.bool_]
    requests: tuple[VehicleRequest, ...]
    dt_s: float

    @property
    def any_request(self) -> bool:
        """Whether any vehicle has a request this period (the common case is none)."""
        return any(r is not VehicleRequest.NONE for r in self.requests)


def step_inputs(
    vehicle_count: int,
    velocity_setpoint_ned_mps: ArrayLike,
    yaw_ned_rad: ArrayLike,
    setpoint_sent: ArrayLike,
    requests: Sequence[VehicleRequest],
    dt_s: float,
) -> StepInputs:
    """Check the shapes and types of one ``step`` call; raises ValueError naming the argument that is wrong.

    Setpoint values are not checked for finiteness: a NaN setpoint is what PX4 refuses (and keeps the previous one),
    which each backend models; a NaN yaw means "keep the heading" (the yaw field is then left out).
    """
    n = vehicle_count
    velocity = np.asarray(velocity_setpoint_ned_mps, dtype=float)
    if velocity.shape != (n, 3):
        raise ValueError(f"velocity_setpoint_ned_mps: expected shape ({n}, 3), got {velocity.shape}")
    yaw = np.asarray(yaw_ned_rad, dtype=float)
    if yaw.shape != (n,):
        raise ValueError(f"yaw_ned_rad: expected shape ({n},), got {yaw.shape}")
    sent = np.asarray(setpoint_sent)
    if sent.shape != (n,) or sent.dtype != np.bool_:
        raise ValueError(f"setpoint_sent: expected a bool array of shape ({n},), got {sent.dtype} {sent.shape}")
    request_tuple = tuple(requests)
    if len(request_tuple) != n:
        raise ValueError(f"requests: expected {n}, got {len(request_tuple)}")
    for r in request_tuple:
        if not isinstance(r, VehicleRequest):
            raise ValueError(f"requests: expected VehicleRequest values, got {r!r}")
    if not (math.isfinite(dt_s) and dt_s > 0.0):
        raise ValueError(f"dt_s: expected a positive finite period, got {dt_s}")
    return StepInputs(velocity, yaw, sent, request_tuple, float(dt_s))


@runtime_checkable
class VehicleBackend(Protocol):
    """N vehicles advanced together by the caller's clock (no wall time, no I/O visible to the caller).

    Contract, for both implementations:

    * ``hover_start(altitude_m)`` is called once, before any ``step``; it returns the state at mission time 0 with
      every vehicle armed, in air, in OFFBOARD, ``altitude_m`` above its pad, at (near) zero velocity.
    * ``step`` applies, at the current mission time ``t``, each vehicle's velocity setpoint (where
      ``setpoint_sent``) and then its request (MAVSDK's ``offboard.start()`` also sends a setpoint before the mode
      switch), advances every vehicle to ``t + dt_s`` and returns the state there. A vehicle without a setpoint this
      period keeps flying its previous one, as PX4 does until COM_OF_LOSS_T runs out.
    * ``kill(index)`` is a power loss: the vehicle stops listening and falls; ``alive`` turns False.
    * Returned states are values: later steps never change them.
    """

    @property
    def vehicle_count(self) -> int:
        """N, the number of vehicles (fixed at construction)."""
        ...

    def hover_start(self, altitude_m: float) -> BackendState:
        """Bring every vehicle to hover ``altitude_m`` [m] above its pad in OFFBOARD; mission time becomes 0."""
        ...

    def step(
        self,
        velocity_setpoint_ned_mps: NDArray[np.float64],
        yaw_ned_rad: NDArray[np.float64],
        setpoint_sent: NDArray[np.bool_],
        requests: Sequence[VehicleRequest],
        dt_s: float,
    ) -> BackendState:
        """One control period of ``dt_s`` [s]: setpoints [(N,3) m/s NED], yaws [(N,) rad; NaN keeps the heading],
        which vehicles got a setpoint [(N,) bool] and one request per vehicle."""
        ...

    def state(self) -> BackendState:
        """The current state (mission time 0 and every vehicle on its pad before ``hover_start``)."""
        ...

    def kill(self, index: int) -> None:
        """Power loss of vehicle ``index`` (fault tests)."""
        ...
