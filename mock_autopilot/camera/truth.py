"""What perception should have found in a rendered frame, read off the renderer's truth mask.

The accuracy tests and the camera benchmark score ``perceive`` against the same reference: the true water and land
centroids, their midpoint (the ``p − q`` of eq 5) and the true shore, all as metric offsets from the point below
the drone [m; east, north], on the same flood models (:data:`ACCURACY_FLOODS`). Pure: mask and pose in, numbers out.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from mock_autopilot.camera.model import CameraModel
from mock_autopilot.camera.render import ground_points_en_m

ACCURACY_FLOODS: Mapping[str, Mapping[str, Any]] = {
    "circle": {"model": "circle"},
    "ellipse": {"model": "ellipse", "orientation_deg": 20.0},
    "nonconvex": {"model": "nonconvex", "phase_rad": 0.7},
    "drift": {"model": "drift", "shape": "circle", "velocity_en_mps": [0.12, 0.09]},
    "terrain": {"model": "terrain", "level_start_m": 1.0, "level_end_m": 2.0, "terrain_size_m": 120.0, "cell_m": 0.5,
                "basin_scale_m": 30.0, "relief_m": 4.0, "roughness": 0.5, "terrain_seed": 7},
    "hydro": {"model": "hydro", "landform": "farmland", "terrain_size_m": 80.0, "mesh_cell_m": 2.0, "relief_m": 0.3,
              "slope": 0.01, "slope_toward_deg": 30.0, "terrain_seed": 7, "run_s": 100.0, "start_s": 30.0,
              "sources": [{"kind": "point", "at_en_m": [0.0, 0.0], "hydrograph_t_s": [0.0, 20.0],
                           "hydrograph_m3ps": [0.0, 1.2]}]},
}
"""One ``[flood]`` table per model for the perception accuracy test and benchmark, so both score the same floods."""


@dataclass(frozen=True)
class TruthReference:
    """The truth a frame's perception result is scored against [m; east, north, relative to the drone]."""

    water_centroid_en_m: NDArray[np.float64]
    land_centroid_en_m: NDArray[np.float64]
    shore_en_m: NDArray[np.float64]
    """Midpoints between 4-neighbour pixel centres of different class, (K, 2)."""

    @property
    def midpoint_en_m(self) -> NDArray[np.float64]:
        """The true ``p − q`` of eq 5."""
        return 0.5 * (self.water_centroid_en_m + self.land_centroid_en_m)


def pixel_offsets_en_m(camera: CameraModel, position_enu_m: Sequence[float], yaw_ned_rad: float,
                       tilt_rad: tuple[float, float] = (0.0, 0.0)) -> NDArray[np.float64]:
    """Each pixel centre's ground point as an offset from the point below the drone, (H, W, 2)."""
    return (ground_points_en_m(camera, position_enu_m, yaw_ned_rad, tilt_rad=tilt_rad)
            - np.asarray(position_enu_m[:2], dtype=float))


def truth_reference(
    camera: CameraModel, position_enu_m: Sequence[float], yaw_ned_rad: float, water_mask: NDArray[np.bool_],
    tilt_rad: tuple[float, float] = (0.0, 0.0),
) -> TruthReference:
    """The reference for a frame whose truth mask holds both water and land (camera tilted by ``tilt_rad``, the
    body's (roll, pitch)): centroids are means of the pixel centres' ground points, as perception measures them."""
    offsets = pixel_offsets_en_m(camera, position_enu_m, yaw_ned_rad, tilt_rad)
    h_pairs = water_mask[:, :-1] != water_mask[:, 1:]
    v_pairs = water_mask[:-1, :] != water_mask[1:, :]
    shore = np.concatenate([0.5 * (offsets[:, :-1][h_pairs] + offsets[:, 1:][h_pairs]),
                            0.5 * (offsets[:-1, :][v_pairs] + offsets[1:, :][v_pairs])])
    return TruthReference(
        water_centroid_en_m=offsets[water_mask].mean(axis=0),
        land_centroid_en_m=offsets[~water_mask].mean(axis=0),
        shore_en_m=shore,
    )


def median_distance_to_shore_m(points_en_m: NDArray[np.float64], reference: TruthReference) -> float:
    """Median distance from each reported edge point to the nearest true shore point [m]."""
    d = np.sqrt(((points_en_m[:, None, :] - reference.shore_en_m[None, :, :]) ** 2).sum(axis=-1)).min(axis=1)
    return float(np.median(d))
