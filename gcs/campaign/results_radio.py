"""The radio's part of docs/RESULTS.md: `circle` over Bernoulli loss and Gilbert–Elliott bursts, ground station on air.

The cells, their campaigns and the target at 50 % average loss in 1 s bursts are defined here once; results_doc
lists the campaigns' commands and calls :func:`radio_section` (pure: rows in, Markdown out).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from gcs.campaign.summary import distribution, distribution_cell

Row = Mapping[str, object]

RADIO_FIXED: tuple[str, ...] = ("radio.latency_s=0.2", "radio.gcs_lossless=false")
"""The ``--set`` assignments every radio cell shares."""
LOSS_CAMPAIGN = "circle-radio-loss"
LOSS_VALUES: tuple[str, ...] = ("0", "0.1", "0.3", "0.5", "0.7")
LOSS_GRID = f"radio.loss={','.join(LOSS_VALUES)}"
BURST_MEANS_S: tuple[str, ...] = ("0.5", "1", "2")
TARGET_BURST_S = "1"
_LOSS_COLUMN = "grid:radio.loss"


def burst_campaign(mean_s: str) -> str:
    """The campaign folder of the bursts with mean length ``mean_s`` [s]."""
    return f"circle-radio-burst-{mean_s}"


def burst_fixed(mean_s: str) -> tuple[str, ...]:
    """The ``--set`` assignments of a burst cell: 50 % average loss in bursts of mean ``mean_s`` seconds."""
    return ("radio.loss=0", "radio.burst_loss=1", f"radio.burst_mean_s={mean_s}", f"radio.burst_gap_s={mean_s}",
            *RADIO_FIXED)


INTRO = (
    "Every cell flies `circle` in improved mode with 200 ms latency and the ground station as a radio node "
    "(`radio.gcs_lossless = false`: the polygon is built from what reaches its antenna at the launch site, directly "
    "or relayed). Bursts keep the average loss at 50 %: the bad state loses everything (`burst_loss = 1`), the good "
    "state nothing (`loss = 0`), and a link is bad half the time (`burst_gap_s = burst_mean_s`), in bursts of the "
    "given mean length. The paper mode is not flown here: it has neither the neighbour filter nor the relay, and "
    "its ring misses the calm targets already (the `circle` table above); these cells ask how much of the improved "
    "mode's margin a bad radio takes away. A cell with fewer seeds than planned says so in n."
)

COLUMNS: tuple[tuple[str, str, str], ...] = (
    ("polygon_iou_final", "polygon IoU", "{:.3f}"),
    ("coverage_final", "coverage", "{:.3f}"),
    ("spacing_cv_final", "spacing CV", "{:.4f}"),
    ("min_pairwise_distance_m", "min pair [m]", "{:.2f}"),
    ("leader_centring_error_last_10s_mean_m", "leader err [m]", "{:.2f}"),
    ("encircle_time_s", "T_enc [s]", "{:.1f}"),
)
TARGETS: tuple[tuple[str, str, str, float], ...] = (
    ("polygon_iou_final", "p5", ">=", 0.97),
    ("coverage_final", "p5", ">=", 0.95),
    ("spacing_cv_final", "p95", "<=", 0.1),
    ("min_pairwise_distance_m", "min", ">=", 1.0),
)
"""(metric, statistic over the seeds, comparison, limit): the target at 50 % average loss in 1 s bursts."""


def _lowest(rows: Sequence[Row], key: str) -> float:
    values = [float(v) for v in (r.get(key) for r in rows) if isinstance(v, (int, float)) and math.isfinite(v)]
    return min(values) if values else math.nan


def _statistic(rows: Sequence[Row], key: str, which: str) -> float:
    if which == "min":
        return _lowest(rows, key)
    stats = distribution(r.get(key) for r in rows)
    return stats.p5 if which == "p5" else stats.p95


def target_lines(rows: Sequence[Row]) -> list[str]:
    """The target table of the 1 s burst cell: each statistic, its limit and whether it holds."""
    lines = ["| metric | statistic over the seeds | target | measured | met |", "|---|---|---|---|---|"]
    title = {key: t for key, t, _ in COLUMNS}
    pattern = {key: p for key, _, p in COLUMNS}
    for key, which, op, limit in TARGETS:
        value = _statistic(rows, key, which)
        met = math.isfinite(value) and (value >= limit if op == ">=" else value <= limit)
        measured = pattern[key].format(value) if math.isfinite(value) else "—"
        lines.append(f"| {title[key]} | {which} | {op} {limit:g} | {measured} | {'yes' if met else 'no'} |")
    return lines


def radio_section(ok_rows: Mapping[str, Sequence[Row]], planned_seeds: int) -> list[str]:
    """Markdown lines: one row per radio cell (n, each column as p50 [p5, p95], the lowest closest pair), then the
    target check."""
    header = ["radio (200 ms latency, ground station on air)", "n", *(t for _, t, _ in COLUMNS),
              "closest pair over all seeds [m]", "pairs < 1 m (runs)"]
    lines = [
        "## A bad radio: Bernoulli loss and bursts on `circle`, the ground station as a radio node",
        "",
        INTRO,
        "",
        "| " + " | ".join(header) + " |",
        "|" + "---|" * len(header),
    ]
    loss_rows = ok_rows.get(LOSS_CAMPAIGN, [])
    cells = [(f"Bernoulli {float(v):.0%}", [r for r in loss_rows if str(r.get(_LOSS_COLUMN)) == v]) for v in LOSS_VALUES]
    cells += [(f"bursts, mean {b} s (50 % average)", list(ok_rows.get(burst_campaign(b), []))) for b in BURST_MEANS_S]
    for label, rows in cells:
        n = len(rows) if len(rows) >= planned_seeds else f"{len(rows)} of {planned_seeds}"
        near = sum(1 for r in rows if isinstance(r.get("near_miss_pairs"), (int, float)) and r["near_miss_pairs"] > 0)
        lowest = _lowest(rows, "min_pairwise_distance_m")
        lines.append("| " + " | ".join([label, str(n), *(distribution_cell(rows, k, p) for k, _, p in COLUMNS),
                                        f"{lowest:.2f}" if math.isfinite(lowest) else "—",
                                        str(near) if rows else "—"]) + " |")
    target_rows = list(ok_rows.get(burst_campaign(TARGET_BURST_S), []))
    lines += [
        "",
        f"Target at 50 % average loss in {TARGET_BURST_S} s bursts ({len(target_rows)} seeds):",
        "",
        *target_lines(target_rows),
        "",
    ]
    return lines
