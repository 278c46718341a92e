"""All SPEC §5 metrics of one run, from its MissionRecord and the true flood: the content of metrics.json.

Per-sample metrics (tracking error, spacing, leader centring, safety) are computed at the record's own rate;
grid coverage and the polygon comparisons are sampled every ``coverage_period_s`` / ``polygon_period_s`` (0.5 s by
default) plus the last sample, which keeps a 60 s, 10 Hz record well under a second and a 200-vehicle one in
seconds. "Final" values are those at the last sample (t = duration); "last 10 s" values average the window
``[t_end - 10 s, t_end]`` as the SPEC §5 targets do.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gcs.metrics.centring import centring_errors_m
from gcs.metrics.coverage import CoverageGrid, footprint_coverage, footprint_side_m
from gcs.metrics.effort import climb_events_from_altitude, path_lengths_m, speeds_mps
from gcs.metrics.encircle import ring_closed_time_s
from gcs.metrics.flood_extent import flood_extent_summary
from gcs.metrics.polygon_quality import hausdorff_m, polygon_iou
from gcs.metrics.recovery import recovery_time_s, vehicle_losses
from gcs.metrics.safety import SafetyStats, pairwise_safety
from gcs.metrics.spacing import spacing_from_arcs
from gcs.metrics.tracking import max_m, rms_m
from gcs.mission_record import MissionRecord, PolygonSample
from gcs.polygon.ring import project_onto_ring, ring_area_m2, ring_perimeter_m
from mission_plan.roles import Role
from mock_autopilot.world.flood_model import FloodModel

SCHEMA = "floodwatch.metrics/1"
LAST_WINDOW_S = 10.0
CV_RECOVERED = 0.1
NEAR_MISS_M = 1.0


def compute_mission_metrics(
    record: MissionRecord,
    flood: FloodModel,
    camera_fov_deg: float,
    *,
    coverage_period_s: float = 0.5,
    polygon_period_s: float = 0.5,
    coverage_cells_per_side: int = 240,
) -> dict[str, Any]:
    """Summary, per-vehicle figures and time series of one run, as plain JSON-ready values (NaN -> None)."""
    t = np.asarray(record.t_s, dtype=float)
    pos = np.asarray(record.positions_enu_m, dtype=float)
    n_t = len(t)
    n_v = len(record.vehicle_ids)
    if pos.shape != (n_t, n_v, 3):
        raise ValueError(f"positions_enu_m has shape {pos.shape}, expected {(n_t, n_v, 3)}")
    alive = _alive_mask(record, n_t, n_v) & np.all(np.isfinite(pos), axis=-1)
    sides = _footprint_sides(record, pos, alive, camera_fov_deg)
    roles = np.array(record.roles)
    boundary = np.flatnonzero(roles == Role.BOUNDARY.value)
    leaders = np.flatnonzero(roles == Role.LEADER.value)

    rings = [np.asarray(flood.boundary_en_m(float(tk)), dtype=float) for tk in t]
    edge = _edge_series(pos, alive, boundary, rings)
    centring = _centring_series(t, pos, alive, leaders, flood)
    safety = pairwise_safety(pos, alive, NEAR_MISS_M)
    cov = _coverage_series(t, pos, alive, sides, boundary, rings, flood, coverage_period_s, coverage_cells_per_side)
    poly = _polygon_series(record.polygons, rings, t, polygon_period_s)

    last = t >= (t[-1] - LAST_WINDOW_S) if n_t else np.zeros(0, bool)
    losses = _losses(record, t, alive, edge["spacing_cv"])

    paths = path_lengths_m(pos, alive)
    speed = speeds_mps(t, pos, alive)
    climbs_truth = climb_events_from_altitude(pos[..., 2], alive)

    summary: dict[str, Any] = {
        **_timing_summary(record, t, len(boundary), edge["max_gap_ratio"]),
        **_edge_summary(edge, last),
        **_polygon_and_coverage_summary(poly, cov),
        **_flood_summary(flood, t),
        "leader_centring_error_final_m": _final(centring),
        "leader_centring_error_last_10s_mean_m": _nanmean(centring[last]),
        **_safety_summary(record.vehicle_ids, safety),
        "losses": len(losses),
        **_motion_summary(record, paths, speed[:, boundary] if len(boundary) else np.zeros((0, 0)), climbs_truth),
        **_refusal_summary(record),
    }
    return _jsonable({
        "schema": SCHEMA, "scenario": record.scenario, "mode": record.mode, "engine": record.engine,
        "seed": record.seed, "camera_fov_deg": camera_fov_deg,
        "footprints": "axis-aligned squares of side 2 h tan(fov/2), rasterised on a grid",
        "coverage_cell_m": cov["cell_m"],
        "summary": summary,
        "losses": losses,
        "near_miss_pairs": [[record.vehicle_ids[i], record.vehicle_ids[j]] for i, j in safety.near_miss_pairs],
        "per_vehicle": _per_vehicle(record, paths, speed, climbs_truth, alive),
        "series": {"t_s": t, "tracking_rms_m": edge["rms"], "tracking_max_m": edge["max"],
                   "spacing_cv": edge["spacing_cv"], "max_gap_ratio": edge["max_gap_ratio"],
                   "leader_centring_error_m": centring, "min_pairwise_distance_m": safety.min_distance_series_m,
                   "alive": alive.sum(axis=1)},
        "coverage_series": {k: cov[k] for k in ("t_s", "coverage", "upper_bound", "overlap_efficiency",
                                                 "flood_area_m2", "drone_ring_iou")},
        "polygon_series": {k: poly[k] for k in ("t_s", "iou", "hausdorff_m", "area_m2", "perimeter_m")},
    })


def _timing_summary(record: MissionRecord, t_s: NDArray[np.float64], boundary_vehicles: int,
                    max_gap_ratio: NDArray[np.float64]) -> dict[str, Any]:
    """The run's length and when the ring closed: the engine's encircling time when it reports one, else the time
    the truth shows the ring closed (the paper's T_enc)."""
    ring_closed = ring_closed_time_s(t_s, max_gap_ratio)
    return {
        "duration_s": float(t_s[-1] - t_s[0]) if len(t_s) else 0.0, "samples": len(t_s),
        "vehicles": len(record.vehicle_ids), "boundary_vehicles": boundary_vehicles,
        "encircle_time_s": record.encircle_time_s if record.encircle_time_s is not None else ring_closed,
        "encircle_time_source": "engine" if record.encircle_time_s is not None else "truth (ring closed)",
        "ring_closed_time_s": ring_closed,
    }


def _flood_summary(flood: FloodModel, t_s: NDArray[np.float64]) -> dict[str, Any]:
    """The flood's final area and, for floods with several wet parts, the caged part against the whole."""
    if not len(t_s):
        return {"flood_area_final_m2": math.nan}
    return {"flood_area_final_m2": float(flood.area_m2(float(t_s[-1]))),
            **flood_extent_summary(flood, float(t_s[0]), float(t_s[-1]))}


def _motion_summary(record: MissionRecord, paths_m: NDArray[np.float64], boundary_speed_mps: NDArray[np.float64],
                    climbs_truth: NDArray[np.int_]) -> dict[str, Any]:
    """How far and fast the fleet flew, and how often it climbed (SPEC's search behaviour), by the engine's count
    and by the altitude truth."""
    n_v = len(record.vehicle_ids)
    return {
        "path_length_total_m": float(paths_m.sum()),
        "path_length_mean_m": float(paths_m.mean()) if n_v else math.nan,
        "boundary_speed_mean_mps": _nanmean(boundary_speed_mps),
        "boundary_speed_max_mps": max_m(boundary_speed_mps),
        "climb_events_total": int(sum(record.climb_events)) if len(record.climb_events) == n_v else None,
        "climb_events_truth_total": int(climbs_truth.sum()),
    }


def _edge_summary(edge: Mapping[str, NDArray[np.float64]], last: NDArray[np.bool_]) -> dict[str, float]:
    """Edge tracking (eq 5) and ring spacing (eqs 6-8), over the run and its last 10 s."""
    return {
        "tracking_rms_m": rms_m(edge["errors"]),
        "tracking_max_m": max_m(edge["errors"]),
        "tracking_rms_last_10s_m": rms_m(edge["errors"][last]),
        "tracking_max_last_10s_m": max_m(edge["errors"][last]),
        "spacing_cv_final": _final(edge["spacing_cv"]),
        "max_gap_ratio_final": _final(edge["max_gap_ratio"]),
        "spacing_cv_last_10s_mean": _nanmean(edge["spacing_cv"][last]),
    }


def _polygon_and_coverage_summary(poly: Mapping[str, Any], cov: Mapping[str, Any]) -> dict[str, float]:
    """The caged polygon against the truth, and the cameras' coverage of the water (SPEC §5)."""
    return {
        "polygon_iou_final": _final(poly["iou"]),
        "polygon_hausdorff_final_m": _final(poly["hausdorff_m"]),
        "polygon_iou_mean": _nanmean(poly["iou"]),
        "polygon_area_final_m2": _final(poly["area_m2"]),
        "drone_ring_iou_final": _final(cov["drone_ring_iou"]),
        "coverage_final": _final(cov["coverage"]),
        "coverage_upper_bound_final": _final(cov["upper_bound"]),
        "overlap_efficiency_final": _final(cov["overlap_efficiency"]),
        "coverage_mean": _nanmean(cov["coverage"]),
    }


def _safety_summary(vehicle_ids: Sequence[int], safety: SafetyStats) -> dict[str, Any]:
    """The closest approach over the run and the pairs that came closer than :data:`NEAR_MISS_M`."""
    return {
        "min_pairwise_distance_m": safety.min_distance_m,
        "closest_pair_ids": [vehicle_ids[i] for i in safety.closest_pair] if safety.closest_pair else None,
        "near_miss_threshold_m": NEAR_MISS_M,
        "near_miss_pairs": len(safety.near_miss_pairs),
        "near_miss_events": safety.near_miss_events,
    }


def _losses(record: MissionRecord, t: NDArray[np.float64], alive: NDArray[np.bool_],
            spacing_cv: NDArray[np.float64]) -> list[dict[str, Any]]:
    """Every vehicle lost during the run, with the ring's recovery time after a boundary drone's loss."""
    return [
        {
            "vehicle_id": record.vehicle_ids[loss.index],
            "role": record.roles[loss.index],
            "t_s": loss.t_s,
            "recovery_time_s": recovery_time_s(t, spacing_cv, loss.t_s, CV_RECOVERED)
            if record.roles[loss.index] == Role.BOUNDARY else math.nan,
        }
        for loss in vehicle_losses(t, alive)
    ]


def _refusal_summary(record: MissionRecord) -> dict[str, Any]:
    """Relayed copies refused as impossible: by the vehicles that reported (None: none did), by the ground station's
    radio node (None: outside the radio)."""
    known = [count for count in record.refused_copies if count is not None]
    return {"relayed_copies_refused": sum(known) if known else None,
            "relayed_copies_refused_ground": record.ground_refused_copies}


def _per_vehicle(record: MissionRecord, paths: NDArray[np.float64], speed: NDArray[np.float64],
                 climbs_truth: NDArray[np.int_], alive: NDArray[np.bool_]) -> dict[str, Any]:
    """Each vehicle's path, speeds, Algorithm 1 climbs (engine and truth), relayed copies it refused and whether it
    flew to the end."""
    n_v = len(record.vehicle_ids)
    climbs_engine = list(record.climb_events) if len(record.climb_events) == n_v else [None] * n_v
    refused = list(record.refused_copies) if len(record.refused_copies) == n_v else [None] * n_v
    return {
        str(vid): {
            "role": record.roles[i],
            "path_length_m": float(paths[i]),
            "mean_speed_mps": _nanmean(speed[:, i]) if len(speed) else math.nan,
            "max_speed_mps": max_m(speed[:, i]) if len(speed) else math.nan,
            "climb_events": climbs_engine[i],
            "climb_events_truth": int(climbs_truth[i]),
            "relayed_copies_refused": refused[i],
            "alive_at_end": bool(alive[-1, i]) if len(alive) else False,
        }
        for i, vid in enumerate(record.vehicle_ids)
    }


def _alive_mask(record: MissionRecord, n_t: int, n_v: int) -> NDArray[np.bool_]:
    alive = np.asarray(record.alive, dtype=bool)
    return alive if alive.shape == (n_t, n_v) else np.ones((n_t, n_v), bool)


def _footprint_sides(record: MissionRecord, pos: NDArray[np.float64], alive: NDArray[np.bool_], fov_deg: float) -> NDArray[np.float64]:
    """The engine's footprint sides when recorded, else 2 h tan(fov/2) from the true altitude."""
    sides = np.asarray(record.footprint_side_m, dtype=float)
    if sides.shape != alive.shape:
        sides = footprint_side_m(pos[..., 2], fov_deg)
    return np.where(alive, sides, 0.0)


def _edge_series(
    pos: NDArray[np.float64], alive: NDArray[np.bool_], boundary: NDArray[np.int_], rings: list[NDArray[np.float64]]
) -> dict[str, NDArray[np.float64]]:
    """Tracking errors (T, n_boundary; NaN where not alive) and spacing CV / max gap ratio per sample."""
    n_t = len(rings)
    errors = np.full((n_t, len(boundary)), np.nan)
    cv = np.full(n_t, np.nan)
    gap = np.full(n_t, np.nan)
    for k in range(n_t):
        live = boundary[alive[k, boundary]]
        if len(live) == 0:
            continue
        proj = project_onto_ring(pos[k, live, :2], rings[k], with_nearest=False)
        errors[k, alive[k, boundary]] = proj.distance_m
        stats = spacing_from_arcs(proj.arc_m, proj.perimeter_m)
        cv[k], gap[k] = stats.cv, stats.max_gap_ratio
    with np.errstate(invalid="ignore"):
        rms = np.sqrt(np.nanmean(errors**2, axis=1)) if errors.shape[1] else np.full(n_t, np.nan)
        mx = np.nanmax(np.where(np.isnan(errors), -np.inf, errors), axis=1) if errors.shape[1] else np.full(n_t, np.nan)
    mx = np.where(np.isfinite(mx), mx, np.nan)
    return {"errors": errors, "rms": rms, "max": mx, "spacing_cv": cv, "max_gap_ratio": gap}


def _centring_series(
    t: NDArray[np.float64], pos: NDArray[np.float64], alive: NDArray[np.bool_], leaders: NDArray[np.int_], flood: FloodModel
) -> NDArray[np.float64]:
    """Mean distance of the alive leaders to the true flood centroid, per sample."""
    out = np.full(len(t), np.nan)
    if len(leaders) == 0:
        return out
    for k, tk in enumerate(t):
        live = leaders[alive[k, leaders]]
        if len(live):
            out[k] = float(np.mean(centring_errors_m(pos[k, live], flood.centroid_en_m(float(tk)))))
    return out


def _sample_indices(t: NDArray[np.float64], period_s: float) -> NDArray[np.int_]:
    """Indices at least ``period_s`` apart, always including the first and the last sample."""
    if len(t) == 0:
        return np.zeros(0, int)
    keep = [0]
    for k in range(1, len(t)):
        if t[k] - t[keep[-1]] >= period_s - 1e-9:
            keep.append(k)
    if keep[-1] != len(t) - 1:
        keep.append(len(t) - 1)
    return np.array(keep)


def _coverage_series(
    t: NDArray[np.float64],
    pos: NDArray[np.float64],
    alive: NDArray[np.bool_],
    sides: NDArray[np.float64],
    boundary: NDArray[np.int_],
    rings: list[NDArray[np.float64]],
    flood: FloodModel,
    period_s: float,
    cells_per_side: int,
) -> dict[str, Any]:
    idx = _sample_indices(t, period_s)
    names = ("coverage", "upper_bound", "overlap_efficiency", "flood_area_m2", "drone_ring_iou")
    out: dict[str, Any] = {name: np.full(len(idx), np.nan) for name in names}
    out["t_s"] = t[idx]
    out["cell_m"] = math.nan
    if len(idx) == 0:
        return out
    lo = np.min([rings[k].min(axis=0) for k in idx], axis=0)
    hi = np.max([rings[k].max(axis=0) for k in idx], axis=0)
    grid = CoverageGrid.around(lo, hi, cells_per_side)
    out["cell_m"] = grid.cell_m
    centres = grid.centres_en_m()
    for row, k in enumerate(idx):
        water = np.asarray(flood.is_water(centres, float(t[k])), dtype=bool)
        stats = footprint_coverage(grid, water, pos[k, :, :2], sides[k])
        out["coverage"][row] = stats.coverage
        out["upper_bound"][row] = stats.upper_bound
        out["overlap_efficiency"][row] = stats.overlap_efficiency
        out["flood_area_m2"][row] = stats.flood_area_m2
        out["drone_ring_iou"][row] = _drone_ring_iou(pos[k], alive[k], boundary, rings[k])
    return out


def _drone_ring_iou(pos_k: NDArray[np.float64], alive_k: NDArray[np.bool_], boundary: NDArray[np.int_], ring: NDArray[np.float64]) -> float:
    """IoU of the polygon through the true boundary-drone positions (ordered along the edge): the 0.90 baseline."""
    live = boundary[alive_k[boundary]]
    if len(live) < 3:
        return math.nan
    arc = project_onto_ring(pos_k[live, :2], ring, with_nearest=False).arc_m
    return polygon_iou(pos_k[live[np.argsort(arc)], :2], ring)


def _polygon_series(
    samples: Sequence[PolygonSample], rings: list[NDArray[np.float64]], t: NDArray[np.float64], period_s: float
) -> dict[str, NDArray[np.float64]]:
    """IoU, Hausdorff, area and perimeter of the ground station's polygons against the truth at the same time."""
    if not samples or len(t) == 0:
        empty = np.zeros(0)
        return {"t_s": empty, "iou": empty, "hausdorff_m": empty, "area_m2": empty, "perimeter_m": empty}
    times = np.array([s.t_s for s in samples], dtype=float)
    chosen = _sample_indices(times, period_s)
    out = {name: np.full(len(chosen), np.nan) for name in ("iou", "hausdorff_m", "area_m2", "perimeter_m")}
    out["t_s"] = times[chosen]
    for row, j in enumerate(chosen):
        ring = np.asarray(samples[j].ring_en_m, dtype=float)
        k = int(np.clip(np.searchsorted(t, times[j]), 0, len(t) - 1))
        if k > 0 and abs(t[k - 1] - times[j]) < abs(t[k] - times[j]):
            k -= 1
        out["iou"][row] = polygon_iou(ring, rings[k])
        out["hausdorff_m"][row] = hausdorff_m(ring, rings[k])
        out["area_m2"][row] = ring_area_m2(ring)
        out["perimeter_m"][row] = ring_perimeter_m(ring)
    return out


def _final(series: NDArray[np.float64]) -> float:
    return float(series[-1]) if len(series) else math.nan


def _finite(values: NDArray[np.float64]) -> NDArray[np.float64]:
    v = np.asarray(values, dtype=float).ravel()
    return v[np.isfinite(v)]


def _nanmean(values: NDArray[np.float64]) -> float:
    v = _finite(values)
    return float(v.mean()) if len(v) else math.nan


def _jsonable(value: Any) -> Any:
    """Plain JSON values: numpy scalars and arrays to Python, NaN/inf to None, floats rounded to 6 decimals."""
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return [_jsonable(v) for v in value.tolist()]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        f = float(value)
        return round(f, 6) if math.isfinite(f) else None
    return value
