"""The weather of N simulated vehicles: the air they fly in, how their velocity loop fights it, what their
estimators get wrong. One object per backend (the lockstep kinematics: the fleet; the mock PX4: one vehicle),
so every vehicle backend flies the same laws (:mod:`mock_autopilot.world.wind`,
:mod:`mock_autopilot.wind_response`, :mod:`mock_autopilot.sensor_errors`); this class only keeps their state and
random streams.

The air is one realisation for the whole mission, drawn from the mission seed alone and advected past the swarm at
the mean wind (Taylor's frozen turbulence seen from a slow swarm): a swarm spans tens of metres, less than the
horizontal Dryden scale (67 m at 10 m), so neighbours a few metres apart feel the same eddies and gusts, as they do
outdoors; independent air per vehicle would shake neighbours against each other by sqrt(2) sigma. Each vehicle's
sensor errors are its own, drawn from the mission seed and the vehicle's id.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from mission_plan.weather import SensorSpec, WindSpec
from mock_autopilot.sensor_errors import (
    SENSOR_RATE_HZ,
    estimated_position_ned_m,
    estimated_yaw_rad,
    initial_sensor_errors,
    sensor_step,
)
from mock_autopilot.wind_response import VelocityLoopGains, disturbance_step, no_disturbance, tilt_from_thrust
from mock_autopilot.world.wind import dryden_scales, initial_wind_state, mean_wind_ned_mps, wind_step

WIND_ESTIMATE_TAU_S = 5.0
"""Time constant [s] of the autopilot's wind estimate (PX4's EKF2 wind states settle over seconds)."""
WIND_UPDATE_S = 0.1
"""Period [s] at which the air is advanced (held in between). The filters are discretised exactly, so a coarser
step keeps the Dryden statistics; 0.1 s is far below the shortest correlation time (L_w / V: 2 s at 10 m in
5 m/s), and it spares the mock PX4's 50 Hz physics four of five filter updates."""
WEATHER_STREAM = 0x57E1
AIR_STREAM = 0xA1
"""Salts of the weather's random streams, so they never repeat another consumer of the mission seed."""


STILL = np.zeros((1, 3))
"""The swarm's ground velocity as the air sees it: at rest, so the eddies pass at the mean wind."""


@dataclass(frozen=True)
class Weather:
    """Everything a backend needs to fly in weather: the ``[wind]`` and ``[sensors]`` keys, the mission seed and
    the nominal flight height [m] the Dryden scales are taken at."""

    wind: WindSpec = field(default_factory=WindSpec)
    sensors: SensorSpec = field(default_factory=SensorSpec)
    seed: int = 1
    height_m: float = 10.0

    @property
    def calm(self) -> bool:
        """Still air and exact sensors: the backends then skip this model entirely."""
        return self.wind.still and self.sensors.exact


def velocity_loop_gains(param: Callable[[str], float]) -> VelocityLoopGains:
    """PX4's velocity-loop gains and tilt limit from its parameters (``param(name)`` -> value)."""
    return VelocityLoopGains(
        xy_p=param("MPC_XY_VEL_P_ACC"), xy_i=param("MPC_XY_VEL_I_ACC"), z_p=param("MPC_Z_VEL_P_ACC"),
        z_i=param("MPC_Z_VEL_I_ACC"), tilt_max_deg=param("MPC_TILTMAX_AIR"),
    )


class WeatherModel:
    """Wind, disturbance and sensor errors of N vehicles (rows in the order of ``vehicle_ids``)."""

    def __init__(self, weather: Weather, vehicle_ids: Sequence[int], gains: VelocityLoopGains,
                 has_gps: Sequence[bool]) -> None:
        n = len(vehicle_ids)
        self.weather = weather
        self.gains = gains
        self.has_gps = np.asarray(has_gps, dtype=bool)
        self.rng = np.random.default_rng([WEATHER_STREAM, weather.seed, *[int(i) for i in vehicle_ids]])
        self.air_rng = np.random.default_rng([WEATHER_STREAM, AIR_STREAM, weather.seed])
        self.scales = dryden_scales(weather.height_m, weather.wind.turbulence)
        self.wind_state = initial_wind_state(1, self.scales, weather.wind.gust_interval_s, self.air_rng)
        self.disturbance = no_disturbance(n)
        self.sensors = initial_sensor_errors(n, weather.sensors, self.rng)
        mean = mean_wind_ned_mps(weather.wind.speed_mps, weather.wind.from_deg)
        self.wind_ned_mps = np.tile(mean, (n, 1))
        self.wind_estimate_ned_mps = np.zeros((n, 3))
        self.thrust_ned_mps2 = np.zeros((n, 3))
        self._wind_t_s: float | None = None
        self._sensor_t_s: float | None = None
        self._moved_ned_m = np.zeros((n, 3))

    def air_step(self, t_s: float, dt_s: float, reference_velocity_ned_mps: NDArray[np.float64],
                 reference_accel_ned_mps2: NDArray[np.float64], airborne: NDArray[np.bool_]) -> NDArray[np.float64]:
        """Advance the air and the velocity loop's fight against it by ``dt_s``; returns the velocity error the
        wind leaves (N,3) [m/s], zero for vehicles on the ground (their error and integrator reset)."""
        t_next = t_s + dt_s
        if self._wind_t_s is None:
            self._wind_t_s = t_s
        if t_next >= self._wind_t_s + WIND_UPDATE_S - 1e-9:
            air, self.wind_state = wind_step(self.wind_state, self.weather.wind, self.scales, self._wind_t_s,
                                             t_next - self._wind_t_s, STILL, self.air_rng)
            self.wind_ned_mps = np.repeat(air, len(self.wind_ned_mps), axis=0)
            self._wind_t_s = t_next
        felt = np.where(airborne[:, None], self.wind_ned_mps, 0.0)
        state, thrust = disturbance_step(self.disturbance, reference_velocity_ned_mps, reference_accel_ned_mps2,
                                         felt, self.gains, dt_s)
        if not airborne.all():
            state.error_mps[~airborne] = 0.0
            state.integrator_mps2[~airborne] = 0.0
        self.disturbance = state
        self.thrust_ned_mps2 = thrust
        keep = math.exp(-dt_s / WIND_ESTIMATE_TAU_S)
        self.wind_estimate_ned_mps = np.where(
            airborne[:, None], keep * self.wind_estimate_ned_mps + (1.0 - keep) * felt, self.wind_estimate_ned_mps)
        return state.error_mps

    def sensor_step(self, t_s: float, dt_s: float, moved_ned_m: NDArray[np.float64]) -> None:
        """Advance the sensor errors by ``dt_s``; they change once per measurement (``SENSOR_RATE_HZ``), so the
        displacement is summed until the next one is due."""
        if self._sensor_t_s is None:
            self._sensor_t_s, self._moved_ned_m = t_s, np.zeros_like(moved_ned_m)
        self._moved_ned_m = self._moved_ned_m + moved_ned_m
        t_next = t_s + dt_s
        if t_next >= self._sensor_t_s + 1.0 / SENSOR_RATE_HZ - 1e-9:
            self.sensors = sensor_step(self.sensors, self.weather.sensors, self._sensor_t_s, t_next - self._sensor_t_s,
                                       self._moved_ned_m, self.rng)
            self._sensor_t_s, self._moved_ned_m = t_next, np.zeros_like(moved_ned_m)

    def estimate(self, true_ned_m: NDArray[np.float64], true_yaw_rad: NDArray[np.float64]
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(position [m NED], yaw [rad]) the estimator reports for the given truth."""
        return (estimated_position_ned_m(self.sensors, true_ned_m, self.has_gps),
                estimated_yaw_rad(self.sensors, true_yaw_rad))

    def tilt_rad(self, yaw_rad: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """True (roll, pitch) [rad] from the thrust of the last step."""
        return tilt_from_thrust(self.thrust_ned_mps2, yaw_rad)
