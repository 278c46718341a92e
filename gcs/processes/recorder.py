"""Fills the :class:`~gcs.mission_record.MissionRecord` from ground truth as the mission flies, and keeps it safe.

Rows are appended on the flood clock (one per ground-truth sample the simulator publishes). Every few seconds the
rows so far are saved to ``record.npz`` in the output folder, so a crash or a Ctrl-C still leaves what was
recorded; the final outputs are written from the same record.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from gcs.mission_record import MissionRecord, PolygonSample


class MissionRecorder:
    def __init__(self, scenario: str, mode: str, seed: int, vehicle_ids: list[int], roles: list[str]) -> None:
        self.scenario, self.mode, self.seed = scenario, mode, seed
        self.vehicle_ids = vehicle_ids
        self.roles = roles
        self._t: list[float] = []
        self._pos: list[NDArray[np.float64]] = []
        self._cmd: list[NDArray[np.float64]] = []
        self._foot: list[NDArray[np.float64]] = []
        self._alive: list[NDArray[np.bool_]] = []
        self.polygons: list[PolygonSample] = []
        self.encircle_time_s: float | None = None
        self.events: list[tuple[float, str]] = []
        self.refused_copies: list[int | None] = []
        self.ground_refused_copies: int | None = None

    def __len__(self) -> int:
        return len(self._t)

    def add(
        self,
        t_s: float,
        positions_enu_m: NDArray[np.float64],
        commands_enu_mps: NDArray[np.float64],
        footprint_side_m: NDArray[np.float64],
        alive: NDArray[np.bool_],
    ) -> None:
        """One row at flood time ``t_s`` (rows must come in increasing time; a repeated time is ignored)."""
        if self._t and t_s <= self._t[-1]:
            return
        self._t.append(float(t_s))
        self._pos.append(np.asarray(positions_enu_m, dtype=float).copy())
        self._cmd.append(np.asarray(commands_enu_mps, dtype=float).copy())
        self._foot.append(np.asarray(footprint_side_m, dtype=float).copy())
        self._alive.append(np.asarray(alive, dtype=bool).copy())

    def latest(self) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
        """The newest row's positions (N, 3) and footprint sides (N,), or None before the first row."""
        return (self._pos[-1], self._foot[-1]) if self._t else None

    def record(self) -> MissionRecord:
        n = len(self.vehicle_ids)
        return MissionRecord(
            scenario=self.scenario,
            mode=self.mode,
            engine="processes",
            seed=self.seed,
            vehicle_ids=list(self.vehicle_ids),
            roles=list(self.roles),
            t_s=np.array(self._t, dtype=float),
            positions_enu_m=np.array(self._pos, dtype=float).reshape(-1, n, 3),
            commands_enu_mps=np.array(self._cmd, dtype=float).reshape(-1, n, 3),
            footprint_side_m=np.array(self._foot, dtype=float).reshape(-1, n),
            alive=np.array(self._alive, dtype=bool).reshape(-1, n),
            polygons=list(self.polygons),
            encircle_time_s=self.encircle_time_s,
            climb_events=[],
            events=list(self.events),
            refused_copies=list(self.refused_copies),
            ground_refused_copies=self.ground_refused_copies,
        )

    def save_snapshot(self, path: Path) -> None:
        """Write the rows so far atomically (``record.npz``; polygons as one array per sample)."""
        rec = self.record()
        tmp = path.with_name(path.name + ".tmp.npz")
        polygons = {f"polygon_{i:05d}": p.ring_en_m for i, p in enumerate(rec.polygons)}
        np.savez(
            tmp,
            t_s=rec.t_s,
            positions_enu_m=rec.positions_enu_m,
            commands_enu_mps=rec.commands_enu_mps,
            footprint_side_m=rec.footprint_side_m,
            alive=rec.alive,
            vehicle_ids=np.array(rec.vehicle_ids),
            roles=np.array(rec.roles),
            polygon_t_s=np.array([p.t_s for p in rec.polygons], dtype=float),
            encircle_time_s=np.array(np.nan if rec.encircle_time_s is None else rec.encircle_time_s),
            **polygons,
        )
        os.replace(tmp, path)
