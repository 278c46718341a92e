"""Weather presets: ``weather = "calm" | "moderate" | "rough"``, each a table of dotted-key defaults.

A preset fills in keys the scenario (its TOML or ``--set``) leaves unset: the user's own keys always win. The
numbers are fixed before any tuning: they are what "moderate" means, never tuned to meet a target. Every preset
jitters the launch pads (``fleet.pad_jitter_m``) and the agents' start times (``fleet.start_jitter_s``) so that two
seeds give two runs. ``vignetting`` is not fixed by the specification: 0.2 / 0.4 is our reading.

Keys of a table the schema does not know are left out (:func:`apply_weather_preset`'s ``known_tables``), so the
preset can name the ``[imaging]`` keys before the imaging schema exists and they flow in once it does.
"""

from __future__ import annotations

import copy
from collections.abc import Collection, Mapping
from typing import Any

from mission_plan.table_fields import ScenarioError

WEATHER_KEY = "weather"
DEFAULT_WEATHER = "calm"

_JITTER: dict[str, Any] = {"fleet.pad_jitter_m": 0.2, "fleet.start_jitter_s": 0.2}

PRESETS: dict[str, dict[str, Any]] = {
    "calm": {
        **_JITTER,
    },
    "moderate": {
        "wind.speed_mps": 5.0, "wind.from_deg": 270.0, "wind.turbulence": "light",
        "wind.gust_speed_mps": 3.0, "wind.gust_duration_s": 3.0, "wind.gust_interval_s": 20.0,
        "sensors.gps_white_sigma_m": 0.3, "sensors.gps_bias_sigma_m": 0.5, "sensors.gps_bias_tau_s": 60.0,
        "sensors.altitude_sigma_m": 0.2, "sensors.heading_sigma_deg": 1.0, "sensors.odometry_drift_frac": 0.01,
        "imaging.exposure_drift": 0.2, "imaging.white_balance_drift": 0.1, "imaging.vignetting": 0.2,
        "imaging.noise_sigma": 3.0, "imaging.exposure_time_s": 0.005, "imaging.jpeg_quality": 80,
        "imaging.cloud_shadow_cover": 0.3, "imaging.sun_glint": True, "imaging.turbid_water_probability": 0.5,
        "imaging.floating_debris": False,
        **_JITTER,
    },
    "rough": {
        "wind.speed_mps": 9.0, "wind.from_deg": 270.0, "wind.turbulence": "moderate",
        "wind.gust_speed_mps": 5.0, "wind.gust_duration_s": 3.0, "wind.gust_interval_s": 20.0,
        "sensors.gps_white_sigma_m": 0.6, "sensors.gps_bias_sigma_m": 1.5, "sensors.gps_bias_tau_s": 60.0,
        "sensors.altitude_sigma_m": 0.4, "sensors.heading_sigma_deg": 3.0, "sensors.odometry_drift_frac": 0.03,
        "imaging.exposure_drift": 0.4, "imaging.white_balance_drift": 0.2, "imaging.vignetting": 0.4,
        "imaging.noise_sigma": 6.0, "imaging.exposure_time_s": 0.005, "imaging.jpeg_quality": 60,
        "imaging.cloud_shadow_cover": 0.5, "imaging.sun_glint": True, "imaging.turbid_water_probability": 1.0,
        "imaging.floating_debris": True,
        **_JITTER,
    },
}
"""Preset name -> dotted key -> value (the specified numbers)."""


def weather_name(raw: Mapping[str, Any]) -> str:
    """The scenario's ``weather`` (default calm); an unknown one raises naming the field and the choices."""
    name = raw.get(WEATHER_KEY, DEFAULT_WEATHER)
    if not isinstance(name, str) or name not in PRESETS:
        raise ScenarioError(f"{WEATHER_KEY}: unknown preset {name!r} ({', '.join(PRESETS)})")
    return name


def apply_weather_preset(raw: Mapping[str, Any], known_tables: Collection[str]) -> dict[str, Any]:
    """A copy of the scenario table with the preset's defaults filled in under the user's own keys.

    A key whose table is not in ``known_tables`` is skipped (module doc); a table the user wrote as a non-table
    value is left alone for validation to name.
    """
    table: dict[str, Any] = copy.deepcopy(dict(raw))
    for dotted_key, value in PRESETS[weather_name(raw)].items():
        table_name, key = dotted_key.split(".", 1)
        if table_name not in known_tables:
            continue
        node = table.setdefault(table_name, {})
        if isinstance(node, dict):
            node.setdefault(key, value)
    return table
