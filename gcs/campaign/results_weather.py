"""The weather's part of docs/RESULTS.md: `circle` under the `calm`, `moderate` and `rough` presets.

The presets (mission_plan/weather_presets.py) put wind, sensor errors and hard imagery on the run; a seed draws all of
them, so these are the tables where seeds act. The campaigns and the targets under `moderate` (improved mode) are
defined here once; results_doc lists the commands and calls :func:`weather_section` (pure: rows in, Markdown out).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from gcs.campaign.grid import Mode
from gcs.campaign.results_radio import target_lines
from gcs.campaign.summary import distribution, distribution_cell

Row = Mapping[str, object]

PRESETS: tuple[str, ...] = ("calm", "moderate", "rough")
TARGET_PRESET = "moderate"
PATH_RATIO_MIN = 1.05
"""Per seed, the whole fleet's path under ``moderate`` is at least this multiple of the calm run's."""
PRESET_MODES: dict[str, tuple[Mode, ...]] = {
    "calm": (Mode.IMPROVED,),
    "moderate": (Mode.PAPER, Mode.IMPROVED),
    "rough": (Mode.PAPER, Mode.IMPROVED),
}
"""Calm is flown in improved mode only: it is the reference of the path-length ratio, and the paper mode's calm
figures are the `circle` table's (the presets add only seeded pad and start jitter to a calm run)."""

COLUMNS: tuple[tuple[str, str, str], ...] = (
    ("polygon_iou_final", "polygon IoU", "{:.3f}"),
    ("coverage_final", "coverage", "{:.3f}"),
    ("spacing_cv_final", "spacing CV", "{:.4f}"),
    ("min_pairwise_distance_m", "min pair [m]", "{:.2f}"),
    ("tracking_rms_last_10s_m", "track RMS last 10 s [m]", "{:.2f}"),
    ("encircle_time_s", "T_enc [s]", "{:.1f}"),
    ("path_length_total_m", "fleet path [m]", "{:.0f}"),
)


def weather_campaign(preset: str) -> str:
    """The campaign folder of ``circle`` under ``preset``."""
    return f"circle-weather-{preset}"


def weather_fixed(preset: str) -> tuple[str, ...]:
    """The ``--set`` assignments of a preset's campaign."""
    return (f"weather={preset}",)


def _of_mode(rows: Sequence[Row], mode: Mode) -> list[Row]:
    return [r for r in rows if r.get("mode") == mode.value]


def _paths_by_seed(rows: Sequence[Row]) -> dict[int, float]:
    """The fleet's total path [m] per seed of the improved-mode rows."""
    return {int(str(r.get("seed"))): float(path) for r in _of_mode(rows, Mode.IMPROVED)
            if isinstance(path := r.get("path_length_total_m"), (int, float)) and math.isfinite(path)}


def path_ratios(weather_rows: Sequence[Row], calm_rows: Sequence[Row]) -> dict[int, float]:
    """Per seed flown in both, the fleet's total path under the weather over the calm run's (improved mode)."""
    calm = _paths_by_seed(calm_rows)
    return {seed: path / calm[seed] for seed, path in _paths_by_seed(weather_rows).items() if calm.get(seed, 0.0) > 0}


def weather_section(ok_rows: Mapping[str, Sequence[Row]], planned_seeds: int) -> list[str]:
    """Markdown lines: a row per preset and mode (each column p50 [p5, p95], closest pair over all seeds, runs
    with a pair under 1 m), the targets under ``moderate``, and the path-length ratio per seed."""
    header = ["weather", "mode", "n", *(t for _, t, _ in COLUMNS), "closest pair over all seeds [m]",
              "runs with a pair < 1 m"]
    lines = [
        "## Weather: wind, sensor errors and hard imagery on `circle`",
        "",
        "Presets fixed before any tuning (`--set weather=...`; mission_plan/weather_presets.py): `calm` has "
        "no wind, noise or image degradation but jitters the launch pads (±0.2 m) and the agents' start times "
        "(±0.2 s) from the seed; `moderate` adds 5 m/s wind from 270° with light Dryden turbulence and gusts, GPS, "
        "altitude, heading and odometry errors, and exposure, white balance, noise, blur, JPEG, cloud shadows, glint "
        "and (in half the seeds) turbid water; `rough` more of each, and floating debris. Metrics are scored on the "
        "true positions; the agents fly on the estimates.",
        "",
        "| " + " | ".join(header) + " |",
        "|" + "---|" * len(header),
    ]
    for preset in PRESETS:
        rows = ok_rows.get(weather_campaign(preset), [])
        for mode in PRESET_MODES[preset]:
            cell = _of_mode(rows, mode)
            n = str(len(cell)) if len(cell) >= planned_seeds else f"{len(cell)} of {planned_seeds}"
            distances = [float(v) for v in (r.get("min_pairwise_distance_m") for r in cell)
                         if isinstance(v, (int, float)) and math.isfinite(v)]
            lowest = f"{min(distances):.2f}" if distances else "—"
            close = str(sum(1 for d in distances if d < 1.0)) if distances else "—"
            lines.append("| " + " | ".join([f"`{preset}`", mode.value, n, *(distribution_cell(cell, k, p) for k, _, p in COLUMNS),
                                            lowest, close]) + " |")
    target_rows = _of_mode(ok_rows.get(weather_campaign(TARGET_PRESET), []), Mode.IMPROVED)
    ratios = path_ratios(ok_rows.get(weather_campaign(TARGET_PRESET), []), ok_rows.get(weather_campaign("calm"), []))
    held = sum(1 for r in ratios.values() if r >= PATH_RATIO_MIN)
    ratio_stats = distribution(ratios.values())
    lines += [
        "",
        f"Targets under `{TARGET_PRESET}`, improved mode ({len(target_rows)} seeds):",
        "",
        *target_lines(target_rows),
        "",
        f"Fleet path under `{TARGET_PRESET}` over the same seed's `calm` run (improved): "
        + (f"p50 {ratio_stats.p50:.3f} [p5 {ratio_stats.p5:.3f}, p95 {ratio_stats.p95:.3f}], at least "
           f"{PATH_RATIO_MIN:g}x in {held} of {len(ratios)} seeds." if ratios else "no seed flown under both yet."),
        "",
    ]
    return lines
