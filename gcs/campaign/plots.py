"""Box plots of a campaign: each metric against each grid key, paper and improved side by side (PNG, Agg).

The metrics plotted are the headline ones of ``summary.md`` plus wall and CPU time (each PNG costs about 0.1 s;
the summary's tables hold every other metric). Without a grid, each metric is plotted against the mode alone. A
box pools every run at that grid value (all seeds, and all values of the other grid keys); whiskers at p5 and p95.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from gcs.campaign.runner import GRID_PREFIX  # noqa: E402
from gcs.campaign.summary import HEADLINE_METRICS, Row, finite_values, grid_keys, modes_present, ok_rows, sort_key  # noqa: E402
from mission_plan.control_params import ControlMode

MODE_COLOURS = {ControlMode.PAPER: "#4c72b0", ControlMode.IMPROVED: "#dd8452"}
PLOT_METRICS = (*HEADLINE_METRICS, ("wall_s", "wall time per run [s]"), ("cpu_s", "CPU time per run [s]"))


def _file_name(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text)


def write_box_plots(rows: Sequence[Row], plots_dir: Path) -> list[Path]:
    """One PNG per scenario, metric and grid key under ``plots_dir``; returns their paths."""
    good = ok_rows(rows)
    plots_dir.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    for scenario in sorted({str(r.get("scenario")) for r in good}):
        scenario_rows = [r for r in good if str(r.get("scenario")) == scenario]
        modes = modes_present(scenario_rows)
        keys = grid_keys(scenario_rows) or [None]
        for metric, title in PLOT_METRICS:
            for key in keys:
                path = plots_dir / _file_name(f"{Path(scenario).stem}__{metric}__{key or 'mode'}.png")
                if _box_plot(scenario_rows, metric, title, key, modes, f"{Path(scenario).stem}", path):
                    written.append(path)
    return written


def _box_plot(rows: Sequence[Row], metric: str, title: str, key: str | None, modes: Sequence[str],
              scenario: str, path: Path) -> bool:
    levels = sorted({str(r.get(GRID_PREFIX + key)) for r in rows}, key=sort_key) if key else [""]
    width = 0.8 / max(len(modes), 1)
    fig, ax = plt.subplots(figsize=(max(4.0, 1.4 * len(levels) * len(modes)), 3.6))
    drawn = False
    try:
        for m_index, mode in enumerate(modes):
            data, positions = [], []
            for l_index, level in enumerate(levels):
                values, _ = finite_values(r.get(metric) for r in rows if r.get("mode") == mode
                                          and (key is None or str(r.get(GRID_PREFIX + key)) == level))
                if values:
                    data.append(values)
                    positions.append(l_index + (m_index - (len(modes) - 1) / 2) * width)
            if data:
                drawn = True
                boxes = ax.boxplot(data, positions=positions, widths=width * 0.9, patch_artist=True,
                                   whis=(5, 95), showfliers=True)
                for patch in boxes["boxes"]:
                    patch.set_facecolor(MODE_COLOURS.get(mode, "#999999"))
                ax.plot([], [], color=MODE_COLOURS.get(mode, "#999999"), linewidth=8, label=mode)
        if not drawn:
            return False
        ax.set_xticks(range(len(levels)), levels if key else ["all runs"])
        ax.set_xlabel(key or "")
        ax.set_ylabel(title)
        ax.set_title(f"{scenario}: {title}", fontsize=10)
        ax.legend(fontsize=8)
        ax.grid(axis="y", alpha=0.3)
        fig.tight_layout()
        fig.savefig(path, dpi=80)
        return True
    finally:
        plt.close(fig)
