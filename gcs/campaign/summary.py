"""Distributions of a campaign's metrics (n, mean, p5, p50, p95) per grid cell and mode, and their Markdown.

Pure: rows in, numbers and text out. Percentiles interpolate linearly between order statistics (numpy's default),
so with 20 runs p5 lies between the lowest two values; with n = 1 every statistic is that value.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from gcs.campaign.grid import Mode
from gcs.campaign.runner import ERROR_COLUMN, GRID_PREFIX

Row = Mapping[str, Any]

HEADLINE_METRICS: tuple[tuple[str, str], ...] = (
    ("encircle_time_s", "T_enc [s]"),
    ("tracking_rms_last_10s_m", "track RMS last 10 s [m]"),
    ("spacing_cv_final", "spacing CV"),
    ("max_gap_ratio_final", "max gap/ideal"),
    ("polygon_iou_final", "polygon IoU"),
    ("polygon_hausdorff_final_m", "Hausdorff [m]"),
    ("coverage_final", "coverage"),
    ("leader_centring_error_last_10s_mean_m", "leader err [m]"),
    ("min_pairwise_distance_m", "min pair [m]"),
    ("near_miss_pairs", "pairs < 1 m"),
)
"""The headline metrics, in SPEC §5's order, with their column titles; the other numeric columns follow them."""

RUN_COLUMNS = frozenset({
    "run_id", "scenario", "mode", "seed", "cell", "overrides", "code_version", ERROR_COLUMN, "worker",
    "scenario_name", "vehicles", "steps", "frames", "sim_s", "near_miss_threshold_m",
})
"""Columns that name or count a run rather than measure it."""


@dataclass(frozen=True)
class Stats:
    """A metric's distribution over runs; ``missing`` counts runs where it had no value (never reached, failed)."""

    n: int
    mean: float
    p5: float
    p50: float
    p95: float
    missing: int = 0

    @property
    def spread(self) -> float:
        """p95 - p5: how much the seeds moved the metric."""
        return self.p95 - self.p5


def finite_values(values: Iterable[Any]) -> tuple[list[float], int]:
    """The finite numbers among ``values`` and how many were missing (None, NaN, text)."""
    kept: list[float] = []
    missing = 0
    for value in values:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            missing += 1
        else:
            kept.append(float(value))
    return kept, missing


def distribution(values: Iterable[Any]) -> Stats:
    """n, mean and the 5th/50th/95th percentiles of the finite values (NaN statistics when there are none)."""
    kept, missing = finite_values(values)
    if not kept:
        return Stats(0, math.nan, math.nan, math.nan, math.nan, missing)
    p5, p50, p95 = (float(v) for v in np.percentile(kept, [5.0, 50.0, 95.0]))
    return Stats(len(kept), float(np.mean(kept)), p5, p50, p95, missing)


def distribution_cell(rows: Iterable[Row], key: str, pattern: str) -> str:
    """A table cell of ``key`` over ``rows``: ``p50 [p5, p95]``, the single value when p5 and p95 read the same,
    ``—`` without values."""
    stats = distribution(r.get(key) for r in rows)
    if stats.n == 0:
        return "—"
    low, mid, high = (pattern.format(v) for v in (stats.p5, stats.p50, stats.p95))
    return mid if low == high else f"{mid} [{low}, {high}]"


def ok_rows(rows: Iterable[Row]) -> list[Row]:
    return [row for row in rows if not row.get(ERROR_COLUMN)]


def failed_rows(rows: Iterable[Row]) -> list[Row]:
    return [row for row in rows if row.get(ERROR_COLUMN)]


def grid_keys(rows: Iterable[Row]) -> list[str]:
    """The grid keys present in the rows (``grid:`` columns), in first-seen order."""
    keys: list[str] = []
    for row in rows:
        for column in row:
            if column.startswith(GRID_PREFIX) and row[column] is not None and column[len(GRID_PREFIX):] not in keys:
                keys.append(column[len(GRID_PREFIX):])
    return keys


def sort_key(text: str) -> tuple[int, float, str]:
    """Grid values in numeric order where they are numbers, else as text."""
    try:
        return (0, float(text), "")
    except ValueError:
        return (1, 0.0, text)


def group_by(rows: Iterable[Row], columns: Sequence[str]) -> dict[tuple[Any, ...], list[Row]]:
    groups: dict[tuple[Any, ...], list[Row]] = {}
    for row in rows:
        groups.setdefault(tuple(row.get(c) for c in columns), []).append(row)
    return groups


def modes_present(rows: Iterable[Row]) -> list[str]:
    """Modes in a fixed order (paper, then improved), only those that occur."""
    seen = {row.get("mode") for row in rows}
    return [m.value for m in Mode if m.value in seen]


def format_number(value: float) -> str:
    """Four significant digits, ``—`` for no value."""
    if value is None or not math.isfinite(value):
        return "—"
    if value == int(value) and abs(value) < 1e6:
        return str(int(value))
    return f"{value:.4g}"


def format_stats(stats: Stats) -> str:
    """``p50 [p5, p95]`` or the single value when they coincide."""
    if stats.n == 0:
        return "—"
    if stats.p5 == stats.p95:
        return format_number(stats.p50)
    return f"{format_number(stats.p50)} [{format_number(stats.p5)}, {format_number(stats.p95)}]"


def cell_sort(cells: Iterable[str], rows: Sequence[Row]) -> list[str]:
    """Grid cells ordered by their grid values (numerically where they are numbers)."""
    keys = grid_keys(rows)
    first: dict[str, Row] = {}
    for row in rows:
        first.setdefault(row.get("cell", "-"), row)
    return sorted(cells, key=lambda c: [sort_key(str(first[c].get(GRID_PREFIX + k, ""))) for k in keys])


def metric_columns(rows: Sequence[Row]) -> list[tuple[str, str]]:
    """(column, title) of every metric in the rows: the headline ones first, then the other numeric columns."""
    headline = [(key, name) for key, name in HEADLINE_METRICS if any(key in r for r in rows)]
    known = {key for key, _ in headline} | RUN_COLUMNS
    others: set[str] = set()
    for row in rows:
        others.update(key for key, value in row.items()
                      if key not in known and not key.startswith(GRID_PREFIX)
                      and isinstance(value, (int, float)) and not isinstance(value, bool))
    return headline + [(key, key) for key in sorted(others)]


def summary_markdown(rows: Sequence[Row], metrics: Sequence[tuple[str, str]] | None = None,
                     title: str = "Campaign summary") -> str:
    """``summary.md``: per scenario, metric and grid cell, n/mean/p5/p50/p95 with the modes side by side."""
    metrics = metric_columns(rows) if metrics is None else metrics
    good = ok_rows(rows)
    bad = failed_rows(rows)
    modes = modes_present(rows)
    out = [f"# {title}", "",
           f"{len(rows)} runs: {len(good)} ok, {len(bad)} failed. Statistics over the ok runs of each grid cell and "
           "mode (their seeds); p5/p50/p95 interpolate linearly between runs; `missing` counts runs where the "
           "metric had no value (e.g. encircling never completed).", ""]
    for (scenario,), scenario_rows in group_by(good, ["scenario"]).items():
        cells = cell_sort({str(r.get("cell", "-")) for r in scenario_rows}, scenario_rows)
        by_cell_mode = group_by(scenario_rows, ["cell", "mode"])
        out += [f"## `{scenario}`", ""]
        header = ["metric", "grid cell"]
        for mode in modes:
            header += [f"{mode} n", f"{mode} mean", f"{mode} p5", f"{mode} p50", f"{mode} p95"]
        for key, name in metrics:
            if not any(key in r for r in scenario_rows):
                continue
            out += [f"### {name} (`{key}`)", "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
            for cell in cells:
                cells_out = [name, cell]
                for mode in modes:
                    stats = distribution(r.get(key) for r in by_cell_mode.get((cell, mode), []))
                    n_text = str(stats.n) + (f" ({stats.missing} missing)" if stats.missing else "")
                    cells_out += [n_text, *(format_number(v) for v in (stats.mean, stats.p5, stats.p50, stats.p95))]
                out.append("| " + " | ".join(cells_out) + " |")
            out.append("")
    if bad:
        out += ["## Failed runs", "", "| run id | scenario | mode | seed | grid cell | error |", "|---|---|---|---|---|---|"]
        for row in sorted(bad, key=lambda r: (str(r.get("cell")), r.get("seed") or 0, str(r.get("mode")))):
            error = str(row.get(ERROR_COLUMN)).replace("|", "\\|")
            out.append(f"| {row.get('run_id')} | {row.get('scenario')} | {row.get('mode')} | {row.get('seed')} | "
                       f"{row.get('cell')} | {error} |")
        out.append("")
    return "\n".join(out)
