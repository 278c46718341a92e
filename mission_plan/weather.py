"""The weather a mission flies in: the ``[wind]`` and ``[sensors]`` tables as frozen values.

``[wind]``: the mean wind at flight height (``speed_mps``, blowing FROM ``from_deg`` clockwise from north),
MIL-F-8785C low-altitude Dryden turbulence (``turbulence`` = none, light, moderate or severe) and "1 - cosine"
gusts (``gust_speed_mps`` peak, ``gust_duration_s``, mean interval ``gust_interval_s``). ``[sensors]``: the errors of
each vehicle's estimator (GPS white noise and Gauss-Markov bias, altitude, heading, odometry drift without GPS).
The laws that use them live with the simulated vehicles (``mock_autopilot.world.wind``,
``mock_autopilot.sensor_errors``); a preset (``weather = "moderate"``) fills these keys in
(:mod:`mission_plan.weather_presets`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any

from mission_plan.table_fields import ScenarioError, number, reject_unknown

TURBULENCE_LEVELS = ("none", "light", "moderate", "severe")


@dataclass(frozen=True)
class WindSpec:
    """Mean wind [m/s, deg FROM, clockwise from north], turbulence severity, gusts [m/s, s, s]."""

    speed_mps: float = 0.0
    from_deg: float = 270.0
    turbulence: str = "none"
    gust_speed_mps: float = 0.0
    gust_duration_s: float = 3.0
    gust_interval_s: float = 20.0

    @property
    def still(self) -> bool:
        """No mean wind, no turbulence, no gusts: the air does nothing."""
        return self.speed_mps == 0.0 and self.turbulence == "none" and self.gust_speed_mps == 0.0


@dataclass(frozen=True)
class SensorSpec:
    """Estimator errors: GPS white σ and bias σ [m] with the bias time constant [s], altitude σ [m], heading σ
    [deg], odometry drift of vehicles without GPS [fraction of the distance flown]; and the relative-position sensor
    every drone carries (the paper's sensing of neighbours, §I): white σ per axis [m], range [m], rate [Hz]. Not part
    of any weather preset: it is the drones' hardware (UWB-class figures), read only while the estimates err."""

    gps_white_sigma_m: float = 0.0
    gps_bias_sigma_m: float = 0.0
    gps_bias_tau_s: float = 60.0
    altitude_sigma_m: float = 0.0
    heading_sigma_deg: float = 0.0
    odometry_drift_frac: float = 0.0
    ranging_sigma_m: float = 0.1
    ranging_range_m: float = 25.0
    ranging_rate_hz: float = 10.0

    @property
    def exact(self) -> bool:
        """No error at all: the estimate is the truth."""
        return all(getattr(self, name) == 0.0 for name in ESTIMATOR_ERROR_KEYS)

    @property
    def ranging_used(self) -> bool:
        """The drones read their relative-position sensors while position estimates err (and only then): those
        without GPS to correct drifting odometry, every drone of improved mode for its collision barrier."""
        return not self.exact and self.ranging_range_m > 0.0

    @property
    def eph_m(self) -> float:
        """Horizontal position accuracy (1σ per axis) a GPS receiver would report [m]."""
        return math.hypot(self.gps_white_sigma_m, self.gps_bias_sigma_m)


WIND_KEYS = frozenset(f.name for f in fields(WindSpec))
SENSOR_KEYS = frozenset(f.name for f in fields(SensorSpec))
ESTIMATOR_ERROR_KEYS = ("gps_white_sigma_m", "gps_bias_sigma_m", "altitude_sigma_m", "heading_sigma_deg",
                        "odometry_drift_frac")


def wind_spec(table: Mapping[str, Any]) -> WindSpec:
    """The ``[wind]`` table as a :class:`WindSpec`; a bad value raises :class:`ScenarioError` naming the field."""
    reject_unknown(table, WIND_KEYS, "wind")
    turbulence = table.get("turbulence", WindSpec.turbulence)
    if turbulence not in TURBULENCE_LEVELS:
        raise ScenarioError(f"wind.turbulence: must be one of {', '.join(TURBULENCE_LEVELS)}, got {turbulence!r}")
    return WindSpec(
        speed_mps=number(table, "speed_mps", WindSpec.speed_mps, "wind", non_negative=True, maximum=30.0),
        from_deg=number(table, "from_deg", WindSpec.from_deg, "wind", minimum=0.0, maximum=360.0),
        turbulence=turbulence,
        gust_speed_mps=number(table, "gust_speed_mps", WindSpec.gust_speed_mps, "wind", non_negative=True),
        gust_duration_s=number(table, "gust_duration_s", WindSpec.gust_duration_s, "wind", positive=True),
        gust_interval_s=number(table, "gust_interval_s", WindSpec.gust_interval_s, "wind", positive=True),
    )


def sensor_spec(table: Mapping[str, Any]) -> SensorSpec:
    """The ``[sensors]`` table as a :class:`SensorSpec`; every σ and the range must be >= 0, the time constant and
    the ranging rate > 0."""
    reject_unknown(table, SENSOR_KEYS, "sensors")
    values = {
        key: number(table, key, getattr(SensorSpec, key), "sensors", non_negative=True)
        for key in SENSOR_KEYS if key not in ("gps_bias_tau_s", "ranging_rate_hz")
    }
    for key in ("gps_bias_tau_s", "ranging_rate_hz"):
        values[key] = number(table, key, getattr(SensorSpec, key), "sensors", positive=True)
    return SensorSpec(**values)
