"""Preview what a drone's downward camera sees: ``python -m mock_autopilot.camera --scenario circle --t 30
--east 16 --north 0 --alt 10 --out frame.png [--mask] [--set KEY=VALUE ...]``.

``--scenario`` takes a scenario name or TOML path (read through ``mission_plan``: its flood table, seed, camera,
weather preset and imaging conditions) and falls back to a built-in flood model name with its defaults (circle,
ellipse, nonconvex, drift, terrain). ``--set`` overrides a scenario key as ``gcs.mission --set`` does (e.g.
``--set weather=moderate``, ``--set imaging.turbid_water_probability=1``), with the same one-line errors.
``--mask`` also writes the ground-truth water mask beside the image as ``<out>_mask.png``.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2

from mission_plan.imaging import ImagingSpec, imaging_spec, wind_vector_en_mps
from mission_plan.scenario_files import apply_override, read_scenario_table, scenario_path
from mission_plan.scenario_schema import TOP_KEYS, camera_spec, check_keys
from mission_plan.table_fields import ScenarioError, integer, sub_table
from mission_plan.weather import wind_spec
from mission_plan.weather_presets import apply_weather_preset, weather_name
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.camera.render import CameraPose, render_frame
from mock_autopilot.world.config import MODEL_NAMES, FloodConfigError, flood_model_from_config
from mock_autopilot.world.flood_model import FloodModel


class PreviewError(Exception):
    """A usage or configuration problem, reported as one line with exit code 2."""


@dataclass(frozen=True)
class PreviewConfig:
    """What to render and where to write it."""

    scenario: str
    t_s: float
    east_m: float
    north_m: float
    altitude_m: float
    yaw_deg: float
    out: Path
    mask: bool
    seed: int | None
    fov_deg: float | None
    width_px: int | None
    height_px: int | None
    overrides: tuple[str, ...] = ()


@dataclass(frozen=True)
class PreviewWorld:
    """What the preview renders: the flood, the camera, the seed and the imaging conditions."""

    flood: FloodModel
    camera: CameraModel
    seed: int
    imaging: ImagingSpec
    wind_en_mps: tuple[float, float]


def _scenario_table(config: PreviewConfig) -> tuple[dict[str, Any], Path | None]:
    """The scenario's table with the ``--set`` overrides and the weather preset applied, and its folder; a name that
    is no scenario but a built-in flood model gives a table holding only that model."""
    try:
        path = scenario_path(config.scenario)
    except ScenarioError as exc:
        if config.scenario not in MODEL_NAMES:
            raise PreviewError(f"--scenario {config.scenario!r}: {exc}") from None
        raw: dict[str, Any] = {"flood": {"model": config.scenario}}
        for assignment in config.overrides:
            apply_override(raw, assignment)
        return raw, None
    return read_scenario_table(path, config.overrides), path.resolve().parent


def _world(config: PreviewConfig) -> PreviewWorld:
    """The flood, camera, seed and imaging the preview uses: from the scenario if one loads, else a built-in model."""
    camera_kw: dict[str, Any] = {}
    try:
        raw, base_dir = _scenario_table(config)
        weather_name(raw)
        raw = apply_weather_preset(raw, TOP_KEYS)
        check_keys(raw)
        flood_table = dict(sub_table(raw, "flood"))
        seed = integer(raw, "seed", 1 if base_dir is not None else 0, "")
        cam = camera_spec(sub_table(raw, "camera"))
        if base_dir is not None or "camera" in raw:
            camera_kw = {"width_px": cam.width_px, "height_px": cam.height_px, "fov_deg": cam.fov_deg}
        imaging = imaging_spec(sub_table(raw, "imaging"))
        wind = wind_spec(sub_table(raw, "wind"))
    except ScenarioError as exc:
        raise PreviewError(str(exc)) from None
    if config.seed is not None:
        seed = config.seed
    for key, value in (("fov_deg", config.fov_deg), ("width_px", config.width_px), ("height_px", config.height_px)):
        if value is not None:
            camera_kw[key] = value
    try:
        flood = flood_model_from_config(flood_table, seed=seed, base_dir=base_dir)
        camera = CameraModel(**camera_kw)
    except (FloodConfigError, ValueError) as exc:
        raise PreviewError(str(exc)) from None
    return PreviewWorld(flood, camera, seed, imaging, wind_vector_en_mps(wind))


def main(config: PreviewConfig) -> int:
    """Render one frame to ``config.out`` (and the truth mask with ``config.mask``)."""
    for name, value in (("--t", config.t_s), ("--east", config.east_m), ("--north", config.north_m),
                        ("--alt", config.altitude_m), ("--yaw", config.yaw_deg)):
        if not math.isfinite(value):
            raise PreviewError(f"{name}: must be a finite number")
    if config.altitude_m <= 0.0:
        raise PreviewError("--alt: must be > 0 m")
    world = _world(config)
    flood, camera = world.flood, world.camera
    frame = render_frame(flood, config.t_s, (config.east_m, config.north_m, config.altitude_m),
                         math.radians(config.yaw_deg), camera, world.seed, pose=CameraPose(wind_en_mps=world.wind_en_mps),
                         imaging=world.imaging)
    if not cv2.imwrite(str(config.out), frame.image_bgr):
        raise PreviewError(f"--out {config.out}: cannot write the image (folder missing or unknown extension?)")
    written = [str(config.out)]
    if config.mask:
        mask_path = config.out.with_name(f"{config.out.stem}_mask{config.out.suffix}")
        if not cv2.imwrite(str(mask_path), frame.water_mask.astype("uint8") * 255):
            raise PreviewError(f"--out {mask_path}: cannot write the mask")
        written.append(str(mask_path))
    side = camera.footprint_side_m(config.altitude_m)
    water = float(frame.water_mask.mean())
    print(f"wrote {', '.join(written)}: {camera.width_px}x{camera.height_px} px, footprint {side:.2f} m, "
          f"water {water:.1%} (truth)")
    return 0


def parse_args(argv: Sequence[str] | None) -> PreviewConfig:
    parser = argparse.ArgumentParser(prog="python -m mock_autopilot.camera", description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenario", default="circle", help="scenario name/path, or a flood model name")
    parser.add_argument("--t", type=float, default=0.0, dest="t_s", help="flood time [s]")
    parser.add_argument("--east", type=float, default=14.0, help="drone east [m, mission ENU]")
    parser.add_argument("--north", type=float, default=0.0, help="drone north [m, mission ENU]")
    parser.add_argument("--alt", type=float, default=10.0, help="height above ground [m]")
    parser.add_argument("--yaw", type=float, default=0.0, help="PX4 yaw [deg, clockwise from north]")
    parser.add_argument("--fov", type=float, default=None, help="horizontal field of view [deg]")
    parser.add_argument("--width", type=int, default=None, help="image width [px]")
    parser.add_argument("--height", type=int, default=None, help="image height [px]")
    parser.add_argument("--seed", type=int, default=None, help="appearance/terrain seed (default: the scenario's)")
    parser.add_argument("--out", type=Path, default=Path("frame.png"), help="output image (PNG)")
    parser.add_argument("--mask", action="store_true", help="also write the truth mask as <out>_mask.png")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                        help="override a scenario parameter, e.g. --set weather=moderate (repeatable)")
    a = parser.parse_args(argv)
    return PreviewConfig(a.scenario, a.t_s, a.east, a.north, a.alt, a.yaw, a.out, a.mask, a.seed, a.fov, a.width,
                         a.height, tuple(a.overrides))


if __name__ == "__main__":
    try:
        sys.exit(main(parse_args(None)))
    except PreviewError as exc:
        print(f"error: {exc}", file=sys.stderr)
        sys.exit(2)
