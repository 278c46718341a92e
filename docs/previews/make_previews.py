"""Regenerate the preview PNGs in this folder, one per flood model and hydro scenario:
``.venv/bin/python docs/previews/make_previews.py [NAME ...]`` (default: all).

Each PNG shows, left to right: the flood from above at t = 0, 30 and 60 s with the drone's camera footprint; the
128x128 camera frame the drone sees at t = 30 s; and what the onboard perception makes of it, drawn like the paper's
Fig. 6 (water centroid blue, land centroid red, their midpoint black, the shore points found in yellow, the image
centre as a cross). For the hydro scenarios (breach, river, pluvial) the map shows the ground and the water depth at
t = 30 s; the camera sees the water shaded by depth, and perception scales by the height above ground.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from gcs.scenario import load_scenario  # noqa: E402
from mock_autopilot.camera.model import CameraModel  # noqa: E402
from mock_autopilot.camera.render import ground_points_en_m, render_frame  # noqa: E402
from mock_autopilot.world.config import flood_model_from_config  # noqa: E402
from mock_autopilot.camera.render import MIN_ALTITUDE_M  # noqa: E402
from mock_autopilot.world.ground import height_above_ground_m  # noqa: E402
from mock_autopilot.world.hydro import HydroFlood  # noqa: E402
from mock_autopilot.world.terrain import TerrainFlood  # noqa: E402
from vehicle_agents.perception.segmentation import perceive  # noqa: E402

MODELS = ("circle", "ellipse", "nonconvex", "drift", "terrain", "breach", "river", "pluvial")
T_S = 30.0
ALTITUDE_M = 10.0
YAW_DEG = 20.0


def preview(name: str, out: Path) -> None:
    scenario = load_scenario(name)
    flood = flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
    camera = CameraModel(scenario.camera.width_px, scenario.camera.height_px, scenario.camera.fov_deg)
    ring = flood.boundary_en_m(T_S)
    centroid = flood.centroid_en_m(T_S)
    # A boundary drone: on the shore on the north-east side, 1 m outside it.
    bearing = np.arctan2(ring[:, 1] - centroid[1], ring[:, 0] - centroid[0])
    edge = ring[int(np.argmin(np.abs(np.angle(np.exp(1j * (bearing - math.radians(40.0)))))))]
    outward = (edge - centroid) / np.linalg.norm(edge - centroid)
    position = (float(edge[0] + outward[0]), float(edge[1] + outward[1]), ALTITUDE_M)
    yaw = math.radians(YAW_DEG)
    frame = render_frame(flood, T_S, position, yaw, camera, scenario.seed)
    result = perceive(frame.image_bgr, max(height_above_ground_m(flood, position), MIN_ALTITUDE_M), camera.fov_deg, yaw)

    fig, axes = plt.subplots(1, 3, figsize=(15, 5.2), gridspec_kw={"width_ratios": [1.15, 1, 1]})
    ax = axes[0]
    if isinstance(flood, TerrainFlood):
        hm = flood.heightmap
        rows, cols = hm.shape
        half_e, half_n = cols * hm.cell_m / 2, rows * hm.cell_m / 2
        ax.imshow(hm.heights_m, cmap="gist_earth", origin="upper", vmin=-2.0, vmax=6.0,
                  extent=(hm.center_en_m[0] - half_e, hm.center_en_m[0] + half_e,
                          hm.center_en_m[1] - half_n, hm.center_en_m[1] + half_n))
        extent = np.abs(flood.boundary_en_m(60.0)).max() + 6
        grid = np.stack(np.meshgrid(np.linspace(-extent, extent, 500), np.linspace(extent, -extent, 500)), axis=-1)
        ax.contourf(grid[..., 0], grid[..., 1], flood.is_water(grid, T_S), levels=[0.5, 1.5], colors=["#3b6fb6"],
                    alpha=0.55)
    if isinstance(flood, HydroFlood):
        grid = flood.grid
        rows, cols = grid.shape
        half = cols * grid.cell_m / 2
        box = (grid.center_en_m[0] - half, grid.center_en_m[0] + half, grid.center_en_m[1] - half,
               grid.center_en_m[1] + half)
        ax.imshow(grid.heights_m, cmap="gist_earth", origin="upper", extent=box)
        depth = np.ma.masked_less_equal(flood.depth_raster_m(T_S), flood.wet_depth_m)
        shown = ax.imshow(depth, cmap="Blues", origin="upper", extent=box, vmin=0.0, vmax=1.0, alpha=0.85)
        fig.colorbar(shown, ax=ax, fraction=0.046, pad=0.02, label=f"depth at t = {T_S:.0f} s [m]")
    for t_s, style in ((0.0, ":"), (T_S, "-"), (60.0, "--")):
        r = flood.boundary_en_m(t_s)
        closed = np.vstack([r, r[:1]])
        ax.plot(closed[:, 0], closed[:, 1], style, color="#1f4e9c", lw=1.6, label=f"edge t = {t_s:.0f} s")
    corners = ground_points_en_m(camera, position, yaw)[[0, 0, -1, -1, 0], [0, -1, -1, 0, 0]]
    ax.plot(corners[:, 0], corners[:, 1], color="#d62728", lw=1.5, label="camera footprint")
    ax.plot(*position[:2], "^", color="#d62728")
    reach = np.abs(flood.boundary_en_m(60.0) - centroid).max() + 8.0
    ax.set_xlim(centroid[0] - reach, centroid[0] + reach)
    ax.set_ylim(centroid[1] - reach, centroid[1] + reach)
    ax.set_aspect("equal")
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_title(f"{name}: flood from above")
    ax.legend(loc="lower left", fontsize=8)

    axes[1].imshow(frame.image_bgr[..., ::-1], interpolation="nearest")
    axes[1].set_title(f"camera frame, t = {T_S:.0f} s, {ALTITUDE_M:.0f} m, yaw {YAW_DEG:.0f}°\n(up = vehicle forward)")
    ax = axes[2]
    ax.imshow(frame.image_bgr[..., ::-1], interpolation="nearest", alpha=0.55)
    ax.contour(frame.water_mask, levels=[0.5], colors=["white"], linewidths=1.0)
    h, w = frame.water_mask.shape
    ax.plot(w / 2, h / 2, "k+", ms=14, mew=2)
    if result.has_edge:
        gsd = result.ground_sample_m
        heading = math.atan2(math.cos(yaw), math.sin(yaw))
        fwd = np.array([math.cos(heading), math.sin(heading)])
        right = np.array([fwd[1], -fwd[0]])

        def to_px(en: np.ndarray) -> np.ndarray:
            en = np.atleast_2d(en)
            return np.stack([w / 2 + (en @ right) / gsd, h / 2 - (en @ fwd) / gsd], axis=-1)

        pts = to_px(result.edge_points_en_m)
        ax.plot(pts[:, 0] - 0.5, pts[:, 1] - 0.5, ".", color="#ffd400", ms=4, label="shore points")
        for value, colour, label in ((result.water_centroid_en_m, "#1f4e9c", "water centroid"),
                                     (result.land_centroid_en_m, "#d62728", "land centroid"),
                                     (result.midpoint_offset_en_m, "black", "midpoint p (eq 5)")):
            p = to_px(value)[0] - 0.5
            ax.plot(p[0], p[1], "o", color=colour, ms=8, mec="white", label=label)
        mp = result.midpoint_offset_en_m
        ax.set_title(f"perception: water {result.water_fraction:.0%}, p − q = ({mp[0]:+.2f} E, {mp[1]:+.2f} N) m\n"
                     "white line: truth edge")
        ax.legend(loc="lower left", fontsize=8)
    for a in axes[1:]:
        a.set_xticks([])
        a.set_yticks([])
    fig.tight_layout()
    fig.savefig(out, dpi=80, bbox_inches="tight")
    plt.close(fig)


if __name__ == "__main__":
    here = Path(__file__).resolve().parent
    for model in sys.argv[1:] or MODELS:
        preview(model, here / f"{model}.png")
        print(f"wrote {here / f'{model}.png'}")
