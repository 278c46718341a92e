"""``python -m gcs.campaign.results_doc``: docs/RESULTS.md from the rows of the campaigns listed in it.

Every table over seeds is a distribution (n, p5, p50, p95) read from ``<campaign>/rows/*.parquet``; nothing is run
here. The campaigns are :data:`CAMPAIGNS`, written into the file as the exact commands that made the rows; a
campaign with fewer rows than planned shows its n, and rerunning its command resumes it. Where the seeds do not
move a metric (the bundled world is calm: no radio loss, no noise; a seed only moves perception slightly) the
tables say so, with the measured spread p95 - p5.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from gcs.campaign.grid import Mode, expand, parse_grid_axis, parse_seeds
from gcs.campaign.results_hydro import hydro_section
from gcs.campaign.results_radio import BURST_MEANS_S, LOSS_CAMPAIGN, LOSS_GRID, RADIO_FIXED, burst_campaign, burst_fixed
from gcs.campaign.results_radio import radio_section
from gcs.campaign.results_weather import PRESET_MODES, weather_campaign, weather_fixed, weather_section
from gcs.campaign.store import read_rows
from gcs.campaign.summary import Stats, distribution, failed_rows, finite_values, ok_rows

Row = Mapping[str, Any]

CAMPAIGN_ROOT = Path("runs/results")

METRICS: tuple[tuple[str, str, str], ...] = (
    ("encircle_time_s", "T_enc [s]", "{:.1f}"),
    ("tracking_rms_last_10s_m", "track RMS last 10 s [m]", "{:.2f}"),
    ("spacing_cv_final", "spacing CV", "{:.3f}"),
    ("max_gap_ratio_final", "max gap/ideal", "{:.2f}"),
    ("polygon_iou_final", "polygon IoU", "{:.3f}"),
    ("polygon_hausdorff_final_m", "Hausdorff [m]", "{:.2f}"),
    ("coverage_final", "coverage", "{:.3f}"),
    ("leader_centring_error_last_10s_mean_m", "leader err [m]", "{:.2f}"),
    ("min_pairwise_distance_m", "min pair [m]", "{:.2f}"),
    ("near_miss_pairs", "pairs < 1 m", "{:.0f}"),
)
"""(row column, title, format): SPEC §5's headline metrics."""

TARGETS: tuple[tuple[str, str, float], ...] = (
    ("encircle_time_s", "<=", 20.0),
    ("spacing_cv_final", "<=", 0.05),
    ("max_gap_ratio_final", "<=", 1.15),
    ("tracking_rms_last_10s_m", "<=", 0.5),
    ("polygon_iou_final", ">=", 0.97),
    ("coverage_final", ">=", 0.97),
    ("leader_centring_error_last_10s_mean_m", "<=", 1.0),
    ("min_pairwise_distance_m", ">=", 1.0),
)
"""The targets the improved mode must meet on ``circle`` in every run."""

NOTHING_MOVED = "seeds change nothing measurable here until noise/loss act"


@dataclass(frozen=True)
class Campaign:
    """One campaign of the results: its folder under :data:`CAMPAIGN_ROOT` and its ``gcs.campaign`` arguments."""

    name: str
    scenario: str
    seeds: str
    grid: tuple[str, ...] = ()
    modes: tuple[Mode, ...] = (Mode.PAPER, Mode.IMPROVED)
    fixed: tuple[str, ...] = ()
    """``--set`` assignments shared by every run of the campaign."""

    def command(self) -> str:
        grid = "".join(f" --grid {g}" for g in self.grid)
        fixed = "".join(f" --set {f}" for f in self.fixed)
        modes = ",".join(m.value for m in self.modes)
        return (f"python -m gcs.campaign {self.scenario} --seeds {self.seeds} --mode {modes}{grid}{fixed} "
                f"--workers 1 --out {CAMPAIGN_ROOT / self.name}")

    def planned_runs(self) -> int:
        return len(expand(self.scenario, self.modes, parse_seeds(self.seeds), [parse_grid_axis(g) for g in self.grid],
                          self.fixed))

    @property
    def plain(self) -> bool:
        """A bundled scenario as it is: no grid, no overrides (a line of the "every scenario" table)."""
        return not self.grid and not self.fixed


CAMPAIGNS: tuple[Campaign, ...] = (
    Campaign("circle", "circle", "1-20"),
    Campaign("ellipse", "ellipse", "1-5"),
    Campaign("nonconvex", "nonconvex", "1-5"),
    Campaign("drift", "drift", "1-5"),
    Campaign("terrain", "terrain", "1-5"),
    Campaign("large", "large", "1-5"),
    Campaign("circle-pdot", "circle", "1-20", ("control.pdot_reading=full,none",)),
    Campaign("breach", "breach", "1-5"),
    Campaign("river", "river", "1-2"),
    Campaign("pluvial", "pluvial", "1-2"),
    Campaign(LOSS_CAMPAIGN, "circle", "1-20", (LOSS_GRID,), (Mode.IMPROVED,), RADIO_FIXED),
    *(Campaign(burst_campaign(b), "circle", "1-20", (), (Mode.IMPROVED,), burst_fixed(b)) for b in BURST_MEANS_S),
    *(Campaign(weather_campaign(p), "circle", "1-20", (), modes, weather_fixed(p)) for p, modes in PRESET_MODES.items()),
)

PDOT_KEY = "grid:control.pdot_reading"


def fmt(value: float, pattern: str) -> str:
    if value is None or not math.isfinite(value):
        return "—"
    return pattern.format(value)


def fmt_stats(stats: Stats, pattern: str) -> str:
    """``p50 [p5, p95]``, the single value when p5 = p95, ``—`` without values."""
    if stats.n == 0:
        return "—"
    low, mid, high = (fmt(v, pattern) for v in (stats.p5, stats.p50, stats.p95))
    return mid if low == high else f"{mid} [{low}, {high}]"


def seed_spread(rows: Sequence[Row]) -> str:
    """Which headline metrics the seeds moved (p95 - p5, and max - min when a single run lies outside), or none.

    "Nothing" is claimed only when every run agrees at the table's precision.
    """
    moved = []
    for key, title, pattern in METRICS:
        values, _ = finite_values(r.get(key) for r in rows)
        if len(values) < 2 or fmt(min(values), pattern) == fmt(max(values), pattern):
            continue
        stats = distribution(values)
        full = fmt(max(values) - min(values), pattern)
        spread = fmt(stats.spread, pattern)
        moved.append(f"{title} {spread}" + (f" (max - min {full})" if full != spread else ""))
    if not rows:
        return "no rows yet: rerun the campaign's command"
    if len(rows) == 1:
        return "one run"
    return ", ".join(moved) if moved else NOTHING_MOVED


def passes(value: Any, op: str, limit: float) -> bool:
    if value is None or not isinstance(value, (int, float)) or not math.isfinite(value):
        return False
    return value <= limit if op == "<=" else value >= limit


def _mode_rows(rows: Sequence[Row], mode: Mode) -> list[Row]:
    return [r for r in rows if r.get("mode") == mode.value]


def targets_table(rows: Sequence[Row]) -> list[str]:
    """Each target: both modes' distributions, the seeds' spread, and whether improved meets it in every run."""
    pattern = {key: p for key, _, p in METRICS}
    title = {key: t for key, t, _ in METRICS}
    lines = ["| metric | target | paper p50 [p5, p95] | paper p95-p5 | improved p50 [p5, p95] | improved p95-p5 "
             "| improved meets target |", "|---|---|---|---|---|---|---|"]
    for key, op, limit in TARGETS:
        cells = [title[key], f"{op} {limit:g}"]
        for mode in (Mode.PAPER, Mode.IMPROVED):
            stats = distribution(r.get(key) for r in _mode_rows(rows, mode))
            cells += [fmt_stats(stats, pattern[key]), fmt(stats.spread, pattern[key]) if stats.n else "—"]
        improved = _mode_rows(rows, Mode.IMPROVED)
        met = sum(passes(r.get(key), op, limit) for r in improved)
        cells.append(f"{'yes' if improved and met == len(improved) else 'no'} ({met}/{len(improved)} runs)")
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def n_text(n: int, planned: int) -> str:
    """``n``, or ``n of planned`` while a campaign is incomplete."""
    return str(n) if n >= planned else f"{n} of {planned}"


def distribution_table(groups: Sequence[tuple[Sequence[str], Sequence[Row], int]], lead: Sequence[str]) -> list[str]:
    """One line per group (lead cells, rows, runs planned): n, each headline metric as p50 [p5, p95], and what
    the seeds moved."""
    header = [*lead, "n", *(title for _, title, _ in METRICS), "what the seeds moved (p95 - p5)"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for cells, rows, planned in groups:
        stats = [fmt_stats(distribution(r.get(key) for r in rows), pattern) for key, _, pattern in METRICS]
        lines.append("| " + " | ".join([*cells, n_text(len(rows), planned), *stats, seed_spread(rows)]) + " |")
    return lines


def _preamble(rows_by_campaign: Mapping[str, Sequence[Row]], stamp: str) -> list[str]:
    """Where the numbers come from, the modes, how to read a cell, and the campaigns with their commands."""
    versions = sorted({str(r.get("code_version")) for rows in rows_by_campaign.values() for r in rows})
    out = [
        "# Results",
        "",
        f"Generated by `python -m gcs.campaign.results_doc` on {stamp} from the rows of the campaigns below "
        f"(code {', '.join(versions) or '—'}). Every number comes from a lockstep run (`gcs.lockstep`: the agents' "
        "onboard core `vehicle_agents.core` for the whole fleet at the scenario's control rate, the kinematic "
        "vehicle backend with PX4's limits, the camera renderer and OpenCV perception at its camera rate, the comms "
        "radio model carrying the state messages in their wire format) scored from ground truth by "
        "`gcs.metrics.compute_mission_metrics`. Do not edit by hand: run the commands, then the generator.",
        "",
        "Modes: `paper` = eqs 4-10 and Algorithm 1 as SPEC §2 reads them (u_c = 1 m/s for every boundary drone until "
        "the leading drones meet, β separation with d = 10 m, eq 9 vertex mean, eq 10 targets at the layer fraction, "
        "ṗ fed forward along the edge normal). `improved` = 3 m/s encircling by each group's leading drone only, "
        "equal-gap consensus along the ring, edge-point tracking, area-centroid leader, and a braking-aware "
        "collision barrier between all roles. Columns: see SPEC §5; 'final' values at the last sample, 'last 10 s' "
        "averaged.",
        "",
        "Each cell is `p50 [p5, p95]` over the seeds (one value when p5 and p95 agree at the shown precision); n "
        "counts the runs. The bundled scenarios are calm (no radio loss or latency, no camera noise): a seed only "
        "moves the flood's seeded details and perception slightly, so the spreads are small, and where they are zero "
        f"the table says \"{NOTHING_MOVED}\". Campaigns with `--grid radio.loss=...` or noise give spreads that mean "
        "something.",
        "",
        "## Campaigns",
        "",
        "The rows come from these commands (one worker each, on this 2-core machine); rerunning one resumes it, "
        "then `python -m gcs.campaign.results_doc` rewrites this file. Per-campaign summaries and box plots are in "
        "each folder (`summary.md`, `plots/`).",
        "",
        "```",
        *(campaign.command() for campaign in CAMPAIGNS),
        "python -m gcs.campaign.results_doc",
        "```",
        "",
        "| campaign | runs planned | rows | failed | wall time per run p50 [p5, p95] [s] | code of its rows |",
        "|---|---|---|---|---|---|",
    ]
    for campaign in CAMPAIGNS:
        rows = rows_by_campaign.get(campaign.name, [])
        wall = distribution(r.get("wall_s") for r in rows)
        code = ", ".join(sorted({str(r.get("code_version")) for r in rows})) or "—"
        out.append(f"| `{campaign.name}` | {campaign.planned_runs()} | {len(rows)} | {len(failed_rows(rows))} | "
                   f"{fmt_stats(wall, '{:.0f}')} | {code} |")
    return out


def _circle_and_scenarios(ok: Mapping[str, Sequence[Row]]) -> list[str]:
    """The targets on `circle` and every bundled scenario in both modes."""
    circle = ok.get("circle", [])
    seeds = next((c.seeds for c in CAMPAIGNS if c.name == "circle"), "")
    out = [
        "",
        f"## Targets on `circle`, seeds {seeds}",
        "",
        f"Runs: paper {n_text(len(_mode_rows(circle, Mode.PAPER)), len(parse_seeds(seeds or '1')))}, improved "
        f"{n_text(len(_mode_rows(circle, Mode.IMPROVED)), len(parse_seeds(seeds or '1')))}.",
        "",
        *targets_table(circle),
        "",
        f"Spread over seeds: paper — {seed_spread(_mode_rows(circle, Mode.PAPER))}; improved — "
        f"{seed_spread(_mode_rows(circle, Mode.IMPROVED))}.",
        "",
        "## Every scenario, both modes",
        "",
    ]
    groups = []
    for campaign in CAMPAIGNS:
        if not campaign.plain:
            continue
        rows = ok.get(campaign.name, [])
        vehicles = next((str(r.get("vehicles")) for r in rows if r.get("vehicles") is not None), "—")
        planned = len(parse_seeds(campaign.seeds))
        for mode in (Mode.PAPER, Mode.IMPROVED):
            groups.append(([f"`{campaign.scenario}`", vehicles, mode.value, campaign.seeds], _mode_rows(rows, mode),
                           planned))
    return [*out, *distribution_table(groups, ["scenario", "vehicles", "mode", "seeds"]), ""]


def _pdot_section(ok: Mapping[str, Sequence[Row]]) -> list[str]:
    """Eq 5's ṗ feed-forward read three ways on `circle`."""
    circle = ok.get("circle", [])
    seeds = next((c.seeds for c in CAMPAIGNS if c.name == "circle"), "")
    pdot_rows = ok.get("circle-pdot", [])
    pdot_groups = []
    pdot_seeds = len(parse_seeds(next((c.seeds for c in CAMPAIGNS if c.name == "circle-pdot"), "1")))
    circle_seeds = len(parse_seeds(seeds or "1"))
    for mode in (Mode.PAPER, Mode.IMPROVED):
        pdot_groups.append(([mode.value, "normal (default)"], _mode_rows(circle, mode), circle_seeds))
        for reading in ("full", "none"):
            pdot_groups.append(([mode.value, reading],
                                [r for r in _mode_rows(pdot_rows, mode) if r.get(PDOT_KEY) == reading], pdot_seeds))
    return [
        "## ṗ feed-forward readings of eq 5 on `circle` (SPEC §2)",
        "",
        "`normal`: only the edge-normal part of ṗ (both modes' default; the rows of the `circle` campaign); `full`: "
        "ṗ as printed (its tangential part is the drone's own sliding along the edge, i.e. positive feedback); "
        "`none`: no feed-forward. Set per run with the scenario key `control.pdot_reading`.",
        "",
        *distribution_table(pdot_groups, ["mode", "ṗ reading"]),
        "",
    ]


def render(rows_by_campaign: Mapping[str, Sequence[Row]], stamp: str) -> str:
    """The whole RESULTS.md from the campaigns' rows (pure)."""
    ok = {name: ok_rows(rows) for name, rows in rows_by_campaign.items()}
    out = [*_preamble(rows_by_campaign, stamp), *_circle_and_scenarios(ok), *_pdot_section(ok)]
    out += hydro_section(ok)
    out += radio_section(ok, len(parse_seeds(next(c.seeds for c in CAMPAIGNS if c.name == LOSS_CAMPAIGN))))
    out += weather_section(ok, len(parse_seeds(next(c.seeds for c in CAMPAIGNS if c.name == weather_campaign("moderate")))))
    failed = [(name, r) for name, rows in rows_by_campaign.items() for r in failed_rows(rows)]
    if failed:
        out += ["## Failed runs", "", "| campaign | mode | seed | grid cell | error |", "|---|---|---|---|---|"]
        out += [f"| {name} | {r.get('mode')} | {r.get('seed')} | {r.get('cell')} | {r.get('error')} |"
                for name, r in failed]
        out.append("")
    return "\n".join(out)


def main(argv: Sequence[str] | None = None) -> int:
    from gcs.one_line_argparse import OneLineArgumentParser

    parser = OneLineArgumentParser(prog="python -m gcs.campaign.results_doc", label="gcs.campaign.results_doc",
                                   description="Write docs/RESULTS.md from the rows of the results campaigns.")
    parser.add_argument("--root", type=Path, default=CAMPAIGN_ROOT, help=f"campaign folders (default {CAMPAIGN_ROOT})")
    parser.add_argument("--out", type=Path, default=Path("docs/RESULTS.md"))
    parser.add_argument("--print-commands", action="store_true", help="print the campaign commands and exit")
    ns = parser.parse_args(sys.argv[1:] if argv is None else argv)
    if ns.print_commands:
        print("\n".join(c.command() for c in CAMPAIGNS))
        return 0
    rows = {c.name: read_rows(ns.root / c.name) for c in CAMPAIGNS}
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    ns.out.parent.mkdir(parents=True, exist_ok=True)
    ns.out.write_text(render(rows, stamp), encoding="utf-8")
    print(f"wrote {ns.out} from {sum(len(r) for r in rows.values())} rows")
    return 0


if __name__ == "__main__":
    sys.exit(main())
