"""A short animated GIF of the run: the flood growing, the UAVs with their camera footprints and recent trails,
and the ground station's caged polygon.

Kept small and quick: at most ``max_frames`` frames (60 by default) at ~400 px, drawn by updating a fixed set of
artists on an Agg canvas (the static axes are drawn once and restored per frame, as matplotlib's blitting does) and
written with Pillow using one shared palette, so a 60-frame GIF takes about a second and weighs a few hundred kB.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection, PathCollection, PolyCollection
from matplotlib.colors import to_rgba
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.text import Text
from numpy.typing import NDArray
from PIL import Image

from gcs.mission_record import MissionRecord, PolygonSample
from gcs.report.trajectories import ROLE_COLOURS, vehicle_colours
from mock_autopilot.world.flood_model import FloodModel

TRAIL_S = 6.0


def frame_indices(n_samples: int, max_frames: int) -> NDArray[np.int_]:
    """At most ``max_frames`` sample indices, evenly spread, always ending on the last sample."""
    if n_samples <= 0:
        return np.zeros(0, int)
    count = max(1, min(max_frames, n_samples))
    return np.unique(np.round(np.linspace(0, n_samples - 1, count)).astype(int))


def polygon_at(samples: Sequence[PolygonSample], t_s: float) -> PolygonSample | None:
    """The latest polygon sample at or before ``t_s`` (None before the first)."""
    best = None
    for sample in samples:
        if sample.t_s <= t_s + 1e-9:
            best = sample
        else:
            break
    return best


@dataclass(frozen=True)
class _Track:
    """The record's arrays the frames are drawn from: times [s], positions [m; ENU], who is alive, footprint sides."""

    t_s: NDArray[np.float64]
    positions_enu_m: NDArray[np.float64]
    alive: NDArray[np.bool_]
    sides_m: NDArray[np.float64]

    @classmethod
    def of(cls, record: MissionRecord) -> _Track:
        pos = np.asarray(record.positions_enu_m, dtype=float)
        alive = np.asarray(record.alive, dtype=bool)
        sides = np.asarray(record.footprint_side_m, dtype=float)
        return cls(np.asarray(record.t_s, dtype=float), pos,
                   alive if alive.shape == pos.shape[:2] else np.ones(pos.shape[:2], bool),
                   sides if sides.shape == pos.shape[:2] else np.zeros(pos.shape[:2]))


@dataclass(frozen=True)
class _Artists:
    """The artists that change from frame to frame (everything else is drawn once)."""

    water: PolyCollection
    footprints: PolyCollection
    trails: LineCollection
    caged_line: Line2D
    dots: PathCollection
    title: Text

    def all(self) -> list[Any]:
        return [self.water, self.footprints, self.trails, self.caged_line, self.dots, self.title]


def _axes(fig: Figure, lo: NDArray[np.float64], hi: NDArray[np.float64]) -> Axes:
    ax = fig.subplots()
    fig.subplots_adjust(left=0.13, right=0.97, bottom=0.2, top=0.94)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("East [m]", fontsize=8)
    ax.set_ylabel("North [m]", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.grid(True, lw=0.3, alpha=0.5)
    return ax


def _artists(ax: Axes, record: MissionRecord, colours: Sequence[str]) -> _Artists:
    """The moving artists, and a legend (with the roles' colours for a fleet too big to tell apart)."""
    big_fleet = len(record.vehicle_ids) > 13
    artists = _Artists(
        water=PolyCollection([], facecolors="#9ecae1", edgecolors="#3182bd", linewidths=1.0, zorder=1),
        footprints=PolyCollection([], facecolors="none", linewidths=0.4 if big_fleet else 0.8, zorder=2),
        trails=LineCollection([], linewidths=1.0, zorder=3),
        caged_line=ax.plot([], [], color="black", lw=1.8, zorder=5)[0],
        dots=ax.scatter(np.zeros(len(colours)), np.zeros(len(colours)), s=8 if big_fleet else 18, c=colours,
                        edgecolors="black", linewidths=0.4, zorder=6),
        title=ax.set_title("", fontsize=9),
    )
    for collection in (artists.water, artists.footprints, artists.trails):
        ax.add_collection(collection)
    for role, colour in ROLE_COLOURS.items():
        if role in record.roles and big_fleet:
            ax.plot([], [], "o", color=colour, ms=4, label=role)
    ax.fill([], [], facecolor="#9ecae1", edgecolor="#3182bd", label="flood (truth)")
    ax.plot([], [], color="grey", lw=0.8, label="camera footprint")
    ax.plot([], [], color="black", lw=1.8, label="caged polygon")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3, fontsize=6.5, frameon=False)
    return artists


def _draw(a: _Artists, k: int, track: _Track, record: MissionRecord, flood: FloodModel, colours: Sequence[str],
          coverage: Callable[[float], float | None]) -> None:
    """Set every moving artist to sample ``k``."""
    tk = float(track.t_s[k])
    a.water.set_verts([np.asarray(flood.boundary_en_m(tk))])
    live = track.alive[k]
    seen = np.flatnonzero(live & (track.sides_m[k] > 0))
    a.footprints.set_verts([_square(track.positions_enu_m[k, i, :2], track.sides_m[k, i]) for i in seen])
    a.footprints.set_edgecolor([to_rgba(colours[i], 0.85) for i in seen])
    start = np.searchsorted(track.t_s, tk - TRAIL_S)
    a.trails.set_segments([track.positions_enu_m[start : k + 1, i, :2] for i in np.flatnonzero(live)])
    a.trails.set_color([colours[i] for i in np.flatnonzero(live)])
    a.dots.set_offsets(np.where(live[:, None], track.positions_enu_m[k, :, :2], np.nan))
    sample = polygon_at(record.polygons, tk)
    ring = np.asarray(sample.ring_en_m, dtype=float) if sample is not None else np.zeros((0, 2))
    if len(ring) >= 3:
        closed = np.vstack([ring, ring[:1]])
        a.caged_line.set_data(closed[:, 0], closed[:, 1])
    else:
        a.caged_line.set_data([], [])
    cov = coverage(tk)
    cov_text = f"   coverage {100 * cov:.0f}%" if cov is not None else ""
    a.title.set_text(f"{record.scenario} ({record.mode})   t = {tk:5.1f} s{cov_text}")


def write_animation(
    record: MissionRecord,
    flood: FloodModel,
    out_path: str | os.PathLike[str],
    *,
    metrics: Mapping[str, Any] | None = None,
    max_frames: int = 60,
    fps: int = 8,
    size_px: int = 420,
) -> Path:
    """Render the run as a GIF into ``out_path``; ``metrics`` (compute_mission_metrics output) adds coverage to titles."""
    track = _Track.of(record)
    colours = vehicle_colours(record)
    coverage = _coverage_lookup(metrics)
    dpi = 100
    fig = Figure(figsize=(size_px / dpi, 1.12 * size_px / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    lo, hi = _extent(record, flood, track.t_s, track.positions_enu_m, track.alive)
    artists = _artists(_axes(fig, lo, hi), record, colours)
    for artist in artists.all():
        artist.set_animated(True)
    canvas = fig.canvas
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)
    images = []
    for k in frame_indices(len(track.t_s), max_frames):
        _draw(artists, int(k), track, record, flood, colours, coverage)
        canvas.restore_region(background)
        for artist in artists.all():
            fig.draw_artist(artist)
        images.append(Image.fromarray(np.asarray(canvas.buffer_rgba())[..., :3].copy()))
    out = Path(out_path)
    _save_gif(images, out, fps)
    return out


def _save_gif(images: list[Image.Image], out: Path, fps: int) -> None:
    """One shared 192-colour palette (from the first and last frames) keeps the GIF small and quick to write."""
    if not images:
        return
    first, last = images[0], images[-1]
    sample = Image.new("RGB", (first.width + last.width, first.height))
    sample.paste(first, (0, 0))
    sample.paste(last, (first.width, 0))
    palette = sample.quantize(colors=192, method=Image.Quantize.MEDIANCUT)
    frames = [im.quantize(palette=palette, dither=Image.Dither.NONE) for im in images]
    frames[0].save(out, format="GIF", save_all=True, append_images=frames[1:], duration=int(1000 / max(fps, 1)), loop=0)


def _square(centre_en_m: NDArray[np.float64], side_m: float) -> NDArray[np.float64]:
    h = side_m / 2.0
    return centre_en_m + np.array([[-h, -h], [h, -h], [h, h], [-h, h]])


def _extent(
    record: MissionRecord, flood: FloodModel, t: NDArray[np.float64], pos: NDArray[np.float64], alive: NDArray[np.bool_]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A square view holding every flood edge, every live position and its footprint, with a small margin."""
    points = [np.asarray(flood.boundary_en_m(float(tk))) for tk in (t[:1].tolist() + t[-1:].tolist())]
    live = pos[alive][:, :2]
    if len(live):
        points.append(live)
    cloud = np.concatenate(points) if points else np.zeros((1, 2))
    cloud = cloud[np.all(np.isfinite(cloud), axis=1)]
    sides = np.asarray(record.footprint_side_m, dtype=float)
    margin = (float(np.nanmax(sides)) / 2.0 if sides.size else 0.0) + 1.0
    lo, hi = cloud.min(axis=0) - margin, cloud.max(axis=0) + margin
    centre, half = (lo + hi) / 2.0, float(np.max(hi - lo)) / 2.0
    return centre - half, centre + half


def _coverage_lookup(metrics: Mapping[str, Any] | None) -> Callable[[float], float | None]:
    """A function t -> latest coverage fraction from the metrics' coverage series (None when unknown)."""
    series = (metrics or {}).get("coverage_series") or {}
    times = np.asarray(series.get("t_s") or [], dtype=float)
    values = list(series.get("coverage") or [])

    def lookup(t_s: float) -> float | None:
        if len(times) == 0:
            return None
        k = int(np.searchsorted(times, t_s + 1e-9)) - 1
        return values[k] if k >= 0 else None

    return lookup
