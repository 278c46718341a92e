"""The ``[imaging]`` table: how hard the downward camera's pictures are, on top of the rendered scene.

Every field defaults to clean imagery (nothing applied). The weather presets (``weather = "moderate"`` ...) fill
these keys; a user's own keys override them. Each bad value raises a
:class:`~mission_plan.table_fields.ScenarioError` whose one-line message names the field.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields
import math
from typing import Any

from mission_plan.table_fields import ScenarioError, integer, number, reject_unknown

MAX_DRIFT_FRACTION = 0.9
"""Exposure and white-balance drifts are fractions of the nominal gain: at 1 or more a channel could go black."""


@dataclass(frozen=True)
class ImagingSpec:
    """Imaging conditions (all off by default).

    ``exposure_drift`` and ``white_balance_drift``: ± fraction of the nominal gain (all channels, or each channel),
    drifting slowly over the mission as auto-exposure and auto-white-balance hunt. ``vignetting``: share of the
    brightness lost in the image corners (0..1). ``noise_sigma``: Gaussian sensor noise [DN of 255].
    ``exposure_time_s``: motion blur as long as the ground moves during the exposure. ``jpeg_quality``: 0 for none,
    else the JPEG quality (1..100) the frame is compressed with. ``cloud_shadow_cover``: fraction of the ground under
    cloud shadow (0..1), drifting with the mean wind. ``sun_glint``: the sun's specular reflection on the water.
    ``turbid_water_probability``: share of mission seeds whose water is turbid brown beside brown soil.
    ``floating_debris``: branches, litter and foam floating on the water.
    """

    exposure_drift: float = 0.0
    white_balance_drift: float = 0.0
    vignetting: float = 0.0
    noise_sigma: float = 0.0
    exposure_time_s: float = 0.0
    jpeg_quality: int = 0
    cloud_shadow_cover: float = 0.0
    sun_glint: bool = False
    turbid_water_probability: float = 0.0
    floating_debris: bool = False

    @property
    def is_clean(self) -> bool:
        """Whether nothing is applied (the rendered scene is the frame)."""
        return self == ImagingSpec()


IMAGING_KEYS = frozenset(f.name for f in fields(ImagingSpec))


def _flag(table: Mapping[str, Any], key: str) -> bool:
    value = table.get(key, getattr(ImagingSpec, key))
    if not isinstance(value, bool):
        raise ScenarioError(f"imaging.{key}: must be true or false, got {value!r}")
    return value


def imaging_spec(table: Mapping[str, Any]) -> ImagingSpec:
    """The ``[imaging]`` table as an :class:`ImagingSpec` (missing keys take the clean defaults)."""
    reject_unknown(table, IMAGING_KEYS, "imaging")
    quality = integer(table, "jpeg_quality", ImagingSpec.jpeg_quality, "imaging", minimum=0)
    if quality > 100:
        raise ScenarioError(f"imaging.jpeg_quality: must be 0 (no JPEG) or 1..100, got {quality}")

    def fraction(key: str, maximum: float = 1.0) -> float:
        return number(table, key, getattr(ImagingSpec, key), "imaging", non_negative=True, maximum=maximum)

    return ImagingSpec(
        exposure_drift=fraction("exposure_drift", MAX_DRIFT_FRACTION),
        white_balance_drift=fraction("white_balance_drift", MAX_DRIFT_FRACTION),
        vignetting=fraction("vignetting"),
        noise_sigma=number(table, "noise_sigma", ImagingSpec.noise_sigma, "imaging", non_negative=True, maximum=64.0),
        exposure_time_s=number(table, "exposure_time_s", ImagingSpec.exposure_time_s, "imaging", non_negative=True,
                               maximum=1.0),
        jpeg_quality=quality,
        cloud_shadow_cover=fraction("cloud_shadow_cover"),
        sun_glint=_flag(table, "sun_glint"),
        turbid_water_probability=fraction("turbid_water_probability"),
        floating_debris=_flag(table, "floating_debris"),
    )


def check_imaging(spec: ImagingSpec) -> None:
    """Range-check an :class:`ImagingSpec` that did not come through :func:`imaging_spec` (a plan file decoded
    into one): the same one-line :class:`ScenarioError` naming the field as a scenario's ``[imaging]`` table."""
    imaging_spec({f.name: getattr(spec, f.name) for f in fields(ImagingSpec)})


def mean_wind_en_mps(scenario: object) -> tuple[float, float]:
    """The mean wind the cloud shadows drift with [m/s; east, north]: the scenario's ``[wind]`` table
    (``speed_mps`` blowing FROM ``from_deg``, clockwise from north) when it has one, else calm."""
    return wind_vector_en_mps(getattr(scenario, "wind", None))


def wind_vector_en_mps(wind: object) -> tuple[float, float]:
    """A ``[wind]`` spec's mean wind as the vector it blows towards [m/s; east, north] (calm for None)."""
    speed = float(getattr(wind, "speed_mps", 0.0) or 0.0)
    if not (math.isfinite(speed) and speed > 0.0):
        return (0.0, 0.0)
    towards = math.radians(float(getattr(wind, "from_deg", 0.0)) + 180.0)
    return (speed * math.sin(towards), speed * math.cos(towards))
