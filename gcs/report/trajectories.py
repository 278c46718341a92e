"""The trajectory plot, in the manner of the paper's Fig. 8: every UAV's trace, the true flood edge at several times,
and the ground station's final caged polygon.

Up to 13 vehicles get the paper's own colours (UAV 1 red, 2 blue, 3 green, ...); larger fleets are coloured by role
so the picture stays readable. Figures are drawn on matplotlib's Agg canvas directly (no pyplot, no display, no
global backend state), which is safe in a ground station with threads.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from gcs.metrics.polygon_quality import polygon_iou
from gcs.mission_record import MissionRecord
from mission_plan.roles import Role
from mock_autopilot.world.flood_model import FloodModel

PAPER_COLOURS = [
    "#e41a1c",  # red
    "#1f5fd6",  # blue
    "#2ca02c",  # green
    "#7b3294",  # purple
    "#e6b800",  # yellow (darkened to read on white)
    "#08306b",  # dark blue
    "#00441b",  # dark green
    "#f781bf",  # pink
    "#ff7f00",  # orange
    "#6baed6",  # light blue
    "#74c476",  # light green
    "#c51b7d",  # dark pink
    "#808000",  # olive
]
ROLE_COLOURS = {Role.BOUNDARY: "#e6a700", Role.LEADER: "#d62728", Role.FOLLOWER: "#2ca02c"}
ROLE_MARKERS = {Role.BOUNDARY: "^", Role.LEADER: "*", Role.FOLLOWER: "s"}
EDGE_SHADES = ["#9ecae1", "#6baed6", "#3182bd", "#08519c", "#08306b"]


def vehicle_colours(record: MissionRecord) -> list[str]:
    """One colour per vehicle: the paper's palette for small fleets, role colours for big ones."""
    if len(record.vehicle_ids) <= len(PAPER_COLOURS):
        return PAPER_COLOURS[: len(record.vehicle_ids)]
    return [ROLE_COLOURS.get(role, "#555555") for role in record.roles]


def edge_times_s(t_s: np.ndarray, count: int = 4) -> list[float]:
    """``count`` evenly spread sample times from the first to the last."""
    if len(t_s) == 0:
        return []
    return sorted({float(t) for t in np.linspace(float(t_s[0]), float(t_s[-1]), count)})


def plot_trajectories(record: MissionRecord, flood: FloodModel, out_path: str | os.PathLike[str], title: str = "") -> Path:
    """Draw the Fig. 8-style plot into ``out_path`` (PNG) and return the path."""
    fig = build_trajectory_figure(record, flood, title)
    out = Path(out_path)
    fig.savefig(out, dpi=130)
    return out


def build_trajectory_figure(record: MissionRecord, flood: FloodModel, title: str = "") -> Figure:
    """The trajectory figure itself (so a caller may show or save it)."""
    t = np.asarray(record.t_s, dtype=float)
    pos = np.asarray(record.positions_enu_m, dtype=float)
    alive = np.asarray(record.alive, dtype=bool)
    if alive.shape != pos.shape[:2]:
        alive = np.ones(pos.shape[:2], bool)
    big_fleet = len(record.vehicle_ids) > len(PAPER_COLOURS)
    colours = vehicle_colours(record)

    fig = Figure(figsize=(8.6, 6.6), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    times = edge_times_s(t)
    if times:
        final_edge = np.asarray(flood.boundary_en_m(times[-1]))
        ax.fill(final_edge[:, 0], final_edge[:, 1], color="#c6dbef", alpha=0.45, lw=0, zorder=0)
    shades = EDGE_SHADES[-len(times) :] if len(times) <= len(EDGE_SHADES) else EDGE_SHADES
    for tk, shade in zip(times, shades):
        edge = np.asarray(flood.boundary_en_m(tk))
        closed = np.vstack([edge, edge[:1]])
        ax.plot(closed[:, 0], closed[:, 1], ls="--", lw=1.2, color=shade, zorder=1, label=f"flood edge, t = {tk:.0f} s")

    line_width = 0.7 if big_fleet else 1.4
    for i, vid in enumerate(record.vehicle_ids):
        live = alive[:, i]
        if not live.any():
            continue
        track = pos[live, i, :2]
        label = None if big_fleet else f"UAV {vid} ({record.roles[i]})"
        ax.plot(track[:, 0], track[:, 1], color=colours[i], lw=line_width, alpha=0.9, zorder=3, label=label)
        ax.plot(*track[0], "o", ms=3.5, color=colours[i], mec="white", mew=0.5, zorder=4)
        end_marker = ROLE_MARKERS.get(record.roles[i], "o") if live[-1] else "X"
        size = (9 if end_marker == "*" else 6.5) * (0.6 if big_fleet else 1.0)
        ax.plot(*track[-1], end_marker, ms=size, color=colours[i], mec="black", mew=0.4 if big_fleet else 0.6, zorder=5)

    if record.polygons:
        final = record.polygons[-1]
        ring = np.asarray(final.ring_en_m, dtype=float)
        if len(ring) >= 3:
            closed = np.vstack([ring, ring[:1]])
            iou = polygon_iou(ring, flood.boundary_en_m(final.t_s))
            ax.plot(closed[:, 0], closed[:, 1], color="black", lw=2.2, zorder=6, label=f"caged polygon, t = {final.t_s:.0f} s (IoU {iou:.3f})")
    if big_fleet:
        for role, colour in ROLE_COLOURS.items():
            if role in record.roles:
                ax.plot([], [], color=colour, lw=2, label=f"{role} ({record.roles.count(role)})")
    ax.plot([], [], "o", color="grey", ms=4, label="start")
    ax.plot([], [], "X", color="grey", ms=6, label="lost")

    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.set_xlabel("East [m]")
    ax.set_ylabel("North [m]")
    ax.set_title(title or f"{record.scenario}: UAV traces ({record.mode} mode, {record.engine} engine, seed {record.seed})")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    return fig
