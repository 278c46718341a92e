"""What only a simulation can tell the ground station: ground truth recorded as the mission flies, and the live
polygon IoU and footprint coverage measured against the simulated flood.

An operator station flying real drones has no truth and no flood model; it runs without this object and loses
nothing but these measurements (the caged polygon, the vehicles and the agents are watched the same way).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from comms.latest_buffer import LatestValueBuffer
from comms.messages import GroundTruth, decode
from gcs.metrics.coverage import CoverageGrid, footprint_coverage
from gcs.metrics.polygon_quality import polygon_iou
from gcs.processes.recorder import MissionRecorder
from gcs.scenario import Scenario
from mission_plan.geometry import footprint_side_m
from mock_autopilot.world.config import flood_model_from_config
from mock_autopilot.world.flood_model import FloodModel


class SimulationEvaluation:
    """Ground truth from the simulator bridge, recorded on the flood clock, and the live quality figures."""

    def __init__(self, scenario: Scenario, duration_s: float, vehicle_ids: list[int], recorder: MissionRecorder) -> None:
        self.scenario = scenario
        self.vehicle_ids = vehicle_ids
        self.recorder = recorder
        self.flood: FloodModel = flood_model_from_config(scenario.flood, seed=scenario.seed, base_dir=scenario.source_dir)
        self.truth: GroundTruth | None = None
        self.polygon_iou = math.nan
        self.coverage = math.nan
        self._grid = CoverageGrid.around(*_flood_box(self.flood, duration_s), max_cells_per_side=100)

    def poll_truth(self, buf: LatestValueBuffer, mission_t_s: float) -> float:
        """Keep the newest ground-truth sample from the bridge; returns the mission clock [s] it carries."""
        for item in buf.drain():
            truth = decode(GroundTruth, item.payload)
            if truth is not None and (self.truth is None or truth.t_s >= self.truth.t_s):
                self.truth = truth
                mission_t_s = truth.t_s
        return mission_t_s

    def record(self, flood_clock_start_s: float, lost: set[int] | dict[int, float]) -> None:
        """Append the newest truth sample to the record (positions, velocities, footprints, who is alive)."""
        truth = self.truth
        if truth is None or truth.t_s < flood_clock_start_s:
            return
        index = {vid: i for i, vid in enumerate(truth.vehicle_ids)}
        n = len(self.vehicle_ids)
        positions = np.full((n, 3), np.nan)
        velocities = np.zeros((n, 3))
        alive = np.zeros(n, dtype=bool)
        for row, vid in enumerate(self.vehicle_ids):
            i = index.get(vid)
            if i is None:
                continue
            positions[row] = truth.positions_enu_m[i]
            if truth.velocities_enu_mps:
                velocities[row] = truth.velocities_enu_mps[i]
            alive[row] = (not truth.alive or truth.alive[i]) and vid not in lost
        sides = footprint_side_m(np.clip(positions[:, 2], 0.0, None), self.scenario.camera.fov_deg)
        sides = np.where(alive & np.isfinite(sides), sides, 0.0)
        self.recorder.add(truth.t_s - flood_clock_start_s, positions, velocities, sides, alive)

    def measure(self, ring_en_m: NDArray[np.float64] | list, flood_t_s: float) -> None:
        """Live IoU of the caged polygon against the true flood, and the footprint coverage of the water."""
        if len(ring_en_m) >= 3:
            self.polygon_iou = polygon_iou(ring_en_m, self.flood.boundary_en_m(flood_t_s))
        latest = self.recorder.latest()
        if latest is not None:
            positions, sides = latest
            water = np.asarray(self.flood.is_water(self._grid.centres_en_m(), flood_t_s), dtype=bool)
            self.coverage = footprint_coverage(self._grid, water, positions[:, :2], sides).coverage


def _flood_box(flood: FloodModel, duration_s: float) -> tuple[np.ndarray, np.ndarray]:
    """A box holding the flood over the whole run, for the live coverage grid."""
    rings = [np.asarray(flood.boundary_en_m(t), dtype=float) for t in np.linspace(0.0, duration_s, 5)]
    points = np.concatenate(rings)
    return points.min(axis=0) - 2.0, points.max(axis=0) + 2.0
