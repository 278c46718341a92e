"""What one simulated PX4 vehicle is made of and what it knows: its configuration, its state, and the facts
derived from the state (landed state, position validity, offboard proof of life).

The commander (:mod:`mock_autopilot.commander`), the position controller (:mod:`mock_autopilot.position_control`)
and the MAVLink front end (:mod:`mock_autopilot.vehicle`) each change their own part of this state; telemetry
reads a frozen snapshot of it (:mod:`mock_autopilot.telemetry`).
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field, replace
from enum import Enum
from typing import Mapping

import numpy as np
from numpy.typing import NDArray
from pymavlink.dialects.v20 import common as mavlink

from comms.frames import GeodeticHome
from comms.px4 import LandedState, Px4Mode
from mock_autopilot.battery import Battery
from mock_autopilot.kinematics import KinematicLimits, KinematicState
from mock_autopilot.px4_params import ParamStore
from mock_autopilot.px4_streams import DEFAULT_PROFILE
from mock_autopilot.setpoints import OffboardSetpoint
from mock_autopilot.stream_schedule import StreamSchedule
from mock_autopilot.weather_model import Weather, WeatherModel, velocity_loop_gains

LAND_DETECT_S = 0.5
GROUND_TOLERANCE_M = 0.05
GRAVITY_MPS2 = 9.81

NO_ACCEL = np.zeros(3)
NO_ACCEL.flags.writeable = False


class RtlPhase(Enum):
    """The legs of PX4's return: climb to RTL_RETURN_ALT, fly home, land."""

    CLIMB = "climb"
    RETURN = "return"
    LAND = "land"


@dataclass(frozen=True)
class VehicleConfig:
    """How one vehicle is built: instance i has system id i+1 (PX4 SITL), a pad, GPS or not, parameters.

    pad_enu_m [m; mission ENU] is where the vehicle boots (its local NED origin) relative to ``home`` (the mission
    origin); a GPS vehicle reports GLOBAL_POSITION_INT = home + pad + local position.
    """

    instance: int
    has_gps: bool = True
    pad_enu_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    home: GeodeticHome = field(default_factory=GeodeticHome)
    params: Mapping[str, float] = field(default_factory=dict)
    initial_yaw_rad: float = 0.0
    wind_ned_mps: tuple[float, float, float] = (0.0, 0.0, 0.0)
    response_time_s: float = 0.3
    """First-order time constant of the velocity loop [s] (the plant, not a PX4 parameter): the same
    ``kinematics.response_time_s`` the lockstep kinematics read."""
    stream_profile: str = DEFAULT_PROFILE
    system_id: int | None = None
    weather: Weather | None = None
    """Wind and sensor errors (None or calm: still air, exact estimator)."""

    @property
    def sysid(self) -> int:
        """MAVLink system id (instance + 1 unless given)."""
        return self.system_id if self.system_id is not None else self.instance + 1


@dataclass(frozen=True)
class Outgoing:
    """A message to send on one link (``link`` None: on every link)."""

    link: str | None
    message: mavlink.MAVLink_message


def _pad3(values: tuple[float, ...] | NDArray[np.float64]) -> tuple[float, float, float]:
    v = tuple(float(x) for x in values)
    return (v[0], v[1], v[2] if len(v) > 2 else 0.0)


class VehicleState:
    """The state of a PX4 multicopter reduced to its MAVLink behaviour and a point-mass body."""

    def __init__(self, config: VehicleConfig, now_s: float = 0.0) -> None:
        pad = _pad3(config.pad_enu_m)
        if config.pad_enu_m != pad:
            config = replace(config, pad_enu_m=pad)
        self.config = config
        self.system_id = config.sysid
        self.params = ParamStore({"MAV_SYS_ID": self.system_id, **dict(config.params)})
        self.boot_time_s = now_s
        self.ground_below_enu_m = 0.0
        """Ground height below the vehicle above the home ground [m], set by the simulator (DISTANCE_SENSOR)."""
        self.t_s = now_s
        self.body = KinematicState()
        self.yaw_rad = float(config.initial_yaw_rad)
        self.yaw_rate_rad_s = 0.0
        self.accel_ned = NO_ACCEL
        self.armed = False
        self.mode = Px4Mode.AUTO_LOITER
        self.failsafe = False
        self.killed = False
        self.gps_available = config.has_gps
        self.battery = Battery()
        self.home_ned_m = np.zeros(3)
        self.home_valid = config.has_gps
        self.hold_ned = np.zeros(3)
        self.takeoff_down_m = 0.0
        self.rtl_phase = RtlPhase.CLIMB
        self.cruise_speed_mps: float | None = None
        self.offboard_setpoint: OffboardSetpoint | None = None
        self.setpoint_t_s = -math.inf
        self.arm_t_s = now_s
        self.took_off = False
        self.ground_since_s: float | None = now_s
        self.commanded_down_mps = 0.0
        self.last_gcs_heartbeat_s: float | None = None
        self.datalink_lost = False
        self.rejections: Counter[str] = Counter()
        self.handled: Counter[str] = Counter()
        self.pending: list[Outgoing] = []
        self.streams = StreamSchedule(config.stream_profile, now_s)
        self.stream_slack_s = 0.0  # the fleet sets half its tick: a message due within it goes out this tick
        self._limits_version = -1
        self._limits_cache = KinematicLimits()
        self.wind_ned = np.asarray(config.wind_ned_mps, dtype=float) if any(config.wind_ned_mps) else None
        self.weather: WeatherModel | None = None
        if config.weather is not None and not config.weather.calm:
            self.weather = WeatherModel(config.weather, [self.system_id], velocity_loop_gains(self.params.__getitem__),
                                        [config.has_gps])
        self.reference_velocity_ned_mps = np.zeros(3)
        self.wind_warning_t_s: float | None = None
        self.wind_limit_latched = False
        self.estimate_ned_m: NDArray[np.float64] | None = None
        self.estimate_yaw_rad: float | None = None

    @property
    def position_ned_m(self) -> NDArray[np.float64]:
        """Position [m; local NED from the pad] as the estimator knows it: what the vehicle flies on and reports
        (``body`` holds the truth)."""
        return self.body.position_ned_m if self.estimate_ned_m is None else self.estimate_ned_m

    @property
    def wind_estimate_ned_mps(self) -> NDArray[np.float64]:
        """The estimator's wind [m/s NED] (zero in still air; held on the ground, where it is not estimated)."""
        return np.zeros(3) if self.weather is None else self.weather.wind_estimate_ned_mps[0]

    @property
    def reported_yaw_rad(self) -> float:
        """Heading [rad] as the estimator knows it."""
        return self.yaw_rad if self.estimate_yaw_rad is None else self.estimate_yaw_rad

    @property
    def velocity_ned_mps(self) -> NDArray[np.float64]:
        """Velocity [m/s; NED]."""
        return self.body.velocity_ned_mps

    @property
    def battery_remaining(self) -> float:
        """Remaining charge [0..1]."""
        return self.battery.remaining

    @property
    def local_position_valid(self) -> bool:
        return not self.killed

    @property
    def global_position_valid(self) -> bool:
        return self.config.has_gps and self.gps_available and not self.killed

    @property
    def setpoint_received_s(self) -> float:
        """Simulated time [s] the newest valid offboard setpoint arrived (-inf before the first)."""
        return self.setpoint_t_s

    def on_ground(self) -> bool:
        """The body touches the ground (the truth: the ground stops it whatever the estimator thinks)."""
        return float(self.body.position_ned_m[2]) >= -GROUND_TOLERANCE_M

    def landed_for(self, seconds: float) -> bool:
        """The land detector has said "landed" for ``seconds`` beyond its own LAND_DETECT_S."""
        return self.ground_since_s is not None and self.t_s - self.ground_since_s >= LAND_DETECT_S + seconds

    @property
    def landed_state(self) -> LandedState:
        on_ground = self.landed_for(0.0)
        if not self.armed:
            return LandedState.ON_GROUND if self.on_ground() else LandedState.IN_AIR
        if self.mode == Px4Mode.AUTO_TAKEOFF:
            return LandedState.TAKEOFF
        landing = self.mode == Px4Mode.AUTO_LAND or (self.mode == Px4Mode.AUTO_RTL and self.rtl_phase is RtlPhase.LAND)
        if landing and not on_ground:
            return LandedState.LANDING
        return LandedState.ON_GROUND if on_ground else LandedState.IN_AIR

    def offboard_fresh(self, now_s: float) -> bool:
        """Offboard proof of life: the newest valid setpoint is younger than COM_OF_LOSS_T."""
        return now_s - self.setpoint_t_s <= self.params["COM_OF_LOSS_T"]

    def tilt_rad(self) -> tuple[float, float]:
        """(roll, pitch) a multicopter would show for the current horizontal acceleration (in weather: for the
        thrust that holds it against the wind)."""
        if self.weather is not None:
            roll, pitch = self.weather.tilt_rad(np.array([self.yaw_rad]))
            return float(roll[0]), float(pitch[0])
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        a_forward = c * self.accel_ned[0] + s * self.accel_ned[1]
        a_right = -s * self.accel_ned[0] + c * self.accel_ned[1]
        return float(math.atan2(a_right, GRAVITY_MPS2)), float(-math.atan2(a_forward, GRAVITY_MPS2))

    def limits(self) -> KinematicLimits:
        """PX4 velocity-controller limits from the parameters, rebuilt only when a parameter changed.

        The response time is the plant's (``VehicleConfig.response_time_s``), not a parameter: the same value the
        lockstep kinematics read, so both engines fly the same first-order velocity response.
        """
        if self._limits_version != self.params.version:
            self._limits_version = self.params.version
            self._limits_cache = KinematicLimits(
                max_xy_speed_mps=self.params["MPC_XY_VEL_MAX"],
                max_climb_speed_mps=self.params["MPC_Z_VEL_MAX_UP"],
                max_descent_speed_mps=max(self.params["MPC_Z_VEL_MAX_DN"], self.params["MPC_LAND_SPEED"]),
                max_xy_accel_mps2=self.params["MPC_ACC_HOR"],
                max_z_accel_mps2=self.params["MPC_ACC_UP_MAX"],
                response_time_s=self.config.response_time_s,
            )
        return self._limits_cache
