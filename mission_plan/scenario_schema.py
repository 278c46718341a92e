"""A whole mission setup as one frozen :class:`Scenario`, validated from its parsed TOML table.

A scenario says where the mission is (``[home]``), what floods (``[flood]``, validated by the world's
``flood_model_from_config``), who flies (``[fleet]``, :mod:`mission_plan.fleet`), the camera (``[camera]``) and
its imaging conditions (``[imaging]``, :mod:`mission_plan.imaging`), the radio (``[radio]``), the vehicle limits
(``[kinematics]``), the control parameters (``[control]``, with ``[control.paper]``/``[control.improved]``,
:mod:`mission_plan.control_params`) and the weather (``weather`` preset, ``[wind]``, ``[sensors]``,
:mod:`mission_plan.weather`; the preset's defaults are filled in first, under the user's own keys,
:mod:`mission_plan.weather_presets`). Any error raises
:class:`~mission_plan.table_fields.ScenarioError` whose one-line message names the field; an unknown key in any
table but ``[flood]`` names the closest known key here (the flood's own keys are checked with the flood model).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from mission_plan.control_params import MODES, ControlParams, ControlParamsError, params_for_mode
from mission_plan.dynamics import KinematicLimits
from mission_plan.fleet import AUTO_LAUNCH, VehicleSpec, build_fleet, check_fleet_keys
from mission_plan.home import GeodeticHome
from mission_plan.imaging import ImagingSpec, imaging_spec
from mission_plan.roster import RosterEntry
from mission_plan.scenarios import SCENARIO_DIR
from mission_plan.table_fields import ScenarioError, integer, number, reject_unknown, sub_table
from mission_plan.weather import SensorSpec, WindSpec, sensor_spec, wind_spec
from mission_plan.weather_presets import DEFAULT_WEATHER, WEATHER_KEY, apply_weather_preset, weather_name
from mission_plan.jitter import jittered_pads

LaunchResolver = Callable[[Mapping[str, Any], Mapping[str, Any], int, Path], dict[str, Any]]
"""``(fleet, flood, seed, source_dir) -> fleet`` with ``launch_en_m`` filled in: how "auto" pads are resolved."""


@dataclass(frozen=True)
class CameraSpec:
    """Downward camera: image size [px], field of view [deg] and frame rate [Hz of mission time].

    The frame rate is the camera's own, slower than the control loop as on a real drone: between frames the control
    law runs on the newest frame it has (both engines).
    """

    width_px: int = 128
    height_px: int = 128
    fov_deg: float = 60.0
    rate_hz: float = 10.0


@dataclass(frozen=True)
class RadioSpec:
    """Swarm radio: range [m], loss probability, latency and jitter [s], and how it fails like a real one.

    ``loss`` is the Bernoulli loss (the good state's when bursts are on). Gilbert–Elliott bursts per directed link
    are on when ``burst_mean_s`` > 0: ``burst_loss`` is the loss in the bad state, ``burst_mean_s`` the mean burst
    and ``burst_gap_s`` the mean time between bursts [mission s]. ``edge_loss`` is the extra loss at the range limit
    from distance, growing as ``(d / range_m) ** edge_loss_exponent``. ``bandwidth_bytes_per_s`` limits what each
    drone sends (0: unlimited). ``gcs_lossless`` keeps the ground station outside the radio (it hears every drone).
    """

    range_m: float = 25.0
    loss: float = 0.0
    latency_s: float = 0.0
    jitter_s: float = 0.0
    burst_loss: float = 1.0
    burst_mean_s: float = 0.0
    burst_gap_s: float = 0.0
    edge_loss: float = 0.0
    edge_loss_exponent: float = 2.0
    bandwidth_bytes_per_s: float = 0.0
    gcs_lossless: bool = True


@dataclass(frozen=True)
class Scenario:
    """A whole mission setup. ``flood`` and ``control`` stay tables (their owners validate them).

    ``source_dir`` is the folder of the scenario file: relative paths in it (a DEM image) are resolved there.
    """

    name: str
    seed: int
    duration_s: float
    altitude_m: float
    home: GeodeticHome
    flood: Mapping[str, Any]
    vehicles: tuple[VehicleSpec, ...]
    camera: CameraSpec
    radio: RadioSpec
    kinematics: KinematicLimits
    control: Mapping[str, Any]
    control_rate_hz: float = 20.0
    polygon_period_s: float = 1.0
    source_dir: Path = field(default=SCENARIO_DIR)
    weather: str = DEFAULT_WEATHER
    wind: WindSpec = field(default_factory=WindSpec)
    sensors: SensorSpec = field(default_factory=SensorSpec)
    start_jitter_s: float = 0.0
    """Each agent starts its mission up to this long after the flood clock (drawn from the seed by the engine)."""
    imaging: ImagingSpec = field(default=ImagingSpec())

    def roster(self) -> tuple[RosterEntry, ...]:
        """Every vehicle as the others know it."""
        return tuple(v.roster_entry() for v in self.vehicles)

    def control_params(self, mode: str) -> ControlParams:
        """The control parameters of ``mode`` ("paper" or "improved") for every vehicle of this scenario."""
        try:
            return params_for_mode(
                mode, self.control, self.roster(), nominal_altitude_m=self.altitude_m, fov_deg=self.camera.fov_deg,
                state_rate_hz=self.control_rate_hz, odometry_drift_frac=self.sensors.odometry_drift_frac,
                ranging_sigma_m=self.sensors.ranging_sigma_m, ranging_available=self.sensors.ranging_used,
            )
        except ControlParamsError as exc:
            raise ScenarioError(str(exc)) from None


TOP_KEYS = frozenset({"name", "description", "seed", "duration_s", "altitude_m", "control_rate_hz",
                      "polygon_period_s", "home", "flood", "fleet", "camera", "radio", "kinematics", "control",
                      WEATHER_KEY, "wind", "sensors", "imaging"})
_HOME_KEYS = frozenset(f.name for f in fields(GeodeticHome))
_CAMERA_KEYS = frozenset(f.name for f in fields(CameraSpec))
_RADIO_KEYS = frozenset(f.name for f in fields(RadioSpec))
_KINEMATICS_KEYS = frozenset(f.name for f in fields(KinematicLimits))


def check_keys(raw: Mapping[str, Any]) -> None:
    """Reject the first unknown key of the top level and of every table this package owns (not ``[flood]``)."""
    reject_unknown(raw, TOP_KEYS, "")
    for key, known in (("home", _HOME_KEYS), ("camera", _CAMERA_KEYS), ("radio", _RADIO_KEYS),
                       ("kinematics", _KINEMATICS_KEYS)):
        reject_unknown(sub_table(raw, key), known, key)
    check_fleet_keys(sub_table(raw, "fleet"))


def _home(table: Mapping[str, Any]) -> GeodeticHome:
    return GeodeticHome(
        lat_deg=number(table, "lat_deg", GeodeticHome.lat_deg, "home", minimum=-90.0, maximum=90.0),
        lon_deg=number(table, "lon_deg", GeodeticHome.lon_deg, "home", minimum=-180.0, maximum=180.0),
        alt_m=number(table, "alt_m", GeodeticHome.alt_m, "home"),
    )


def camera_spec(table: Mapping[str, Any]) -> CameraSpec:
    """The ``[camera]`` table as a :class:`CameraSpec` (missing keys take the defaults)."""
    return CameraSpec(
        width_px=integer(table, "width_px", CameraSpec.width_px, "camera", minimum=8),
        height_px=integer(table, "height_px", CameraSpec.height_px, "camera", minimum=8),
        fov_deg=number(table, "fov_deg", CameraSpec.fov_deg, "camera", positive=True, maximum=170.0),
        rate_hz=number(table, "rate_hz", CameraSpec.rate_hz, "camera", positive=True, maximum=1000.0),
    )


def _radio(table: Mapping[str, Any]) -> RadioSpec:
    burst_mean_s = number(table, "burst_mean_s", RadioSpec.burst_mean_s, "radio", non_negative=True)
    burst_gap_s = number(table, "burst_gap_s", RadioSpec.burst_gap_s, "radio", non_negative=True)
    if burst_mean_s > 0.0 and burst_gap_s <= 0.0:
        raise ScenarioError(f"radio.burst_gap_s: must be > 0 when radio.burst_mean_s is set, got {burst_gap_s:g}")
    gcs_lossless = table.get("gcs_lossless", RadioSpec.gcs_lossless)
    if not isinstance(gcs_lossless, bool):
        raise ScenarioError(f"radio.gcs_lossless: must be true or false, got {gcs_lossless!r}")
    return RadioSpec(
        range_m=number(table, "range_m", RadioSpec.range_m, "radio", non_negative=True),
        loss=number(table, "loss", RadioSpec.loss, "radio", non_negative=True, maximum=1.0),
        latency_s=number(table, "latency_s", RadioSpec.latency_s, "radio", non_negative=True),
        jitter_s=number(table, "jitter_s", RadioSpec.jitter_s, "radio", non_negative=True),
        burst_loss=number(table, "burst_loss", RadioSpec.burst_loss, "radio", non_negative=True, maximum=1.0),
        burst_mean_s=burst_mean_s,
        burst_gap_s=burst_gap_s,
        edge_loss=number(table, "edge_loss", RadioSpec.edge_loss, "radio", non_negative=True, maximum=1.0),
        edge_loss_exponent=number(table, "edge_loss_exponent", RadioSpec.edge_loss_exponent, "radio", positive=True),
        bandwidth_bytes_per_s=number(table, "bandwidth_bytes_per_s", RadioSpec.bandwidth_bytes_per_s, "radio",
                                     non_negative=True),
        gcs_lossless=gcs_lossless,
    )


def _kinematics(table: Mapping[str, Any]) -> KinematicLimits:
    return KinematicLimits(**{
        key: number(table, key, getattr(KinematicLimits, key), "kinematics", positive=True)
        for key in _KINEMATICS_KEYS
    })


def scenario_from_table(raw: Mapping[str, Any], default_name: str = "scenario", source_dir: Path = SCENARIO_DIR,
                        resolve_launch: LaunchResolver | None = None) -> Scenario:
    """Validate a parsed scenario table (see module doc) into a :class:`Scenario`.

    ``resolve_launch`` fills in ``launch_en_m = "auto"`` (it needs the flood model, which this leaf package does
    not have); without it an "auto" scenario raises a :class:`ScenarioError` that says to use a plan file.
    """
    weather = weather_name(raw)
    raw = apply_weather_preset(raw, TOP_KEYS)
    check_keys(raw)
    name = raw.get("name", default_name)
    if not isinstance(name, str) or not name:
        raise ScenarioError(f"name: must be a non-empty string, got {name!r}")
    description = raw.get("description", "")
    if not isinstance(description, str):
        raise ScenarioError(f"description: must be a string, got {description!r}")
    seed = integer(raw, "seed", 1, "")
    flood = sub_table(raw, "flood")
    if "model" not in flood:
        raise ScenarioError("flood.model: missing (circle, ellipse, nonconvex, drift, terrain or hydro)")
    fleet = sub_table(raw, "fleet")
    if fleet.get("launch_en_m") == AUTO_LAUNCH and resolve_launch is not None:
        fleet = resolve_launch(fleet, flood, seed, source_dir)
    scenario = Scenario(
        name=name,
        seed=seed,
        duration_s=number(raw, "duration_s", 60.0, "", positive=True),
        altitude_m=number(raw, "altitude_m", 10.0, "", positive=True),
        home=_home(sub_table(raw, "home")),
        flood=flood,
        vehicles=jittered_pads(build_fleet(fleet), number(fleet, "pad_jitter_m", 0.0, "fleet", non_negative=True),
                               seed),
        camera=camera_spec(sub_table(raw, "camera")),
        radio=_radio(sub_table(raw, "radio")),
        kinematics=_kinematics(sub_table(raw, "kinematics")),
        control=sub_table(raw, "control"),
        control_rate_hz=number(raw, "control_rate_hz", 20.0, "", positive=True, maximum=1000.0),
        polygon_period_s=number(raw, "polygon_period_s", 1.0, "", positive=True),
        source_dir=source_dir,
        weather=weather,
        wind=wind_spec(sub_table(raw, "wind")),
        sensors=sensor_spec(sub_table(raw, "sensors")),
        start_jitter_s=number(fleet, "start_jitter_s", 0.0, "fleet", non_negative=True),
        imaging=imaging_spec(sub_table(raw, "imaging")),
    )
    for mode in MODES:
        scenario.control_params(mode)
    return scenario
