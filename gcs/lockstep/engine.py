"""One simulated clock, every vehicle stepped in turn: sense, hear, decide, move (see package doc).

The flood clock starts with every vehicle hovering at the nominal altitude over its pad in OFFBOARD (SPEC §4: the
flood clock starts when all are airborne), so take-off is not simulated here. Each control period:

1. true positions -> each drone's own state (odometry = truth here; no drift in lockstep);
2. every drone broadcasts its state; the radio model delivers by range, loss and latency;
3. when a camera frame is due (``[camera] rate_hz``, slower than the control loop) every drone's frame is rendered
   and segmented (``render_frame`` + ``perceive``); in between, each drone keeps its newest result, as an agent does;
4. ``control_step`` of its role gives a velocity setpoint;
5. the ground station's caged polygon is rebuilt from the boundary drones' positions and the edge points their
   state messages carry (each ``polygon_period_s``);
6. ``step_kinematics`` moves every vehicle (PX4-like response and limits).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from comms.frames import enu_to_ned, local_ned_to_mission_enu, ned_to_enu
from comms.radio_model import RadioModel
from gcs.lockstep.radio_link import RadioLink
from gcs.mission_record import MissionRecord, PolygonSample
from gcs.polygon.caged import caged_polygon
from gcs.scenario import Scenario
from mock_autopilot.camera.model import CameraModel
from mock_autopilot.camera.render import render_frame
from mock_autopilot.kinematics import KinematicState, step_kinematics
from mock_autopilot.world.config import flood_model_from_config
from mock_autopilot.world.flood_model import FloodModel
from vehicle_agents.control.memory import ControlMemory
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.step import control_step, initial_memory, own_broadcast
from vehicle_agents.control.types import ROLE_BOUNDARY, OwnState
from vehicle_agents.onboard_view import EDGE_POINTS_PER_MESSAGE
from vehicle_agents.perception.result import PerceptionResult
from vehicle_agents.perception.segmentation import perceive


@dataclass
class LockstepResult:
    """What a run produced: the record for the metrics and reports, the flood it ran on, and run statistics."""

    record: MissionRecord
    flood: FloodModel
    params: ControlParams
    wall_s: float
    cpu_s: float
    """CPU time of this process during the run [s]: the figure a loaded machine does not inflate."""
    steps: int
    frames: int
    radio_heard: int
    radio_lost: int


def reported_edge_points(points_en_m: NDArray[np.float64]) -> NDArray[np.float64]:
    """The edge points a boundary drone's state message carries: at most ``EDGE_POINTS_PER_MESSAGE``, evenly
    subsampled, exactly as the per-process agent sends them (so both engines feed the same polygon)."""
    points = np.asarray(points_en_m, dtype=float).reshape(-1, 2)
    if len(points) > EDGE_POINTS_PER_MESSAGE:
        points = points[np.linspace(0, len(points) - 1, EDGE_POINTS_PER_MESSAGE).round().astype(int)]
    return points


def _perception_for(
    flood: FloodModel, t_s: float, position_enu_m: NDArray[np.float64], camera: CameraModel, seed: int
) -> PerceptionResult:
    frame = render_frame(flood, t_s, position_enu_m, 0.0, camera, seed)
    return perceive(frame.image_bgr, float(position_enu_m[2]), camera.fov_deg, 0.0)


def run_lockstep(
    scenario: Scenario,
    mode: str = "paper",
    seed: int | None = None,
    duration_s: float | None = None,
    control_params: ControlParams | None = None,
    progress: Callable[[float], None] | None = None,
    cameras: str = "all",
) -> LockstepResult:
    """Run ``scenario`` in ``mode`` to ``duration_s`` (default: the scenario's) and return the record.

    ``cameras = "all"`` renders and segments every vehicle's camera at every frame time; ``"boundary"`` only the
    boundary drones' (the only law that reads images, as the process engine's simulator bridge streams by default);
    the others then get no perception result.
    """
    if cameras not in ("all", "boundary"):
        raise ValueError(f"cameras: must be all or boundary, got {cameras!r}")
    seed = scenario.seed if seed is None else seed
    duration_s = scenario.duration_s if duration_s is None else duration_s
    params = control_params if control_params is not None else scenario.control_params(mode)
    flood = flood_model_from_config(scenario.flood, seed=seed, base_dir=scenario.source_dir)
    camera = CameraModel(scenario.camera.width_px, scenario.camera.height_px, scenario.camera.fov_deg)
    vehicles = scenario.vehicles
    n = len(vehicles)
    ids = [v.vehicle_id for v in vehicles]
    pads = np.array([v.pad_enu_m for v in vehicles], dtype=float)
    dt_s = 1.0 / scenario.control_rate_hz
    steps = int(math.floor(duration_s / dt_s + 1e-9))
    radio = RadioLink(
        RadioModel(scenario.radio.range_m, scenario.radio.loss, scenario.radio.latency_s, scenario.radio.jitter_s, seed),
        ids,
        keep_s=params.neighbour_timeout_s + scenario.radio.latency_s + scenario.radio.jitter_s + dt_s,
    )
    states = [KinematicState(position_ned_m=np.array([0.0, 0.0, -scenario.altitude_m]), velocity_ned_mps=np.zeros(3))
              for _ in vehicles]
    memories: list[ControlMemory] = [initial_memory(v.role, v.vehicle_id, params) for v in vehicles]
    boundary_idx = [i for i, v in enumerate(vehicles) if v.role == ROLE_BOUNDARY]
    ring_idx = [ids.index(vid) for vid in params.ring_order() if vid in ids]

    t_rec = np.zeros(steps + 1)
    pos_rec = np.zeros((steps + 1, n, 3))
    cmd_rec = np.zeros((steps + 1, n, 3))
    foot_rec = np.zeros((steps + 1, n))
    polygons: list[PolygonSample] = []
    encircle_time_s: float | None = None
    events: list[tuple[float, str]] = [(0.0, f"lockstep start: {scenario.name}, mode {mode}, seed {seed}, {n} vehicles")]
    next_polygon_t = 0.0
    frame_period_s = 1.0 / scenario.camera.rate_hz
    next_frame_t = 0.0
    perceptions: list[PerceptionResult | None] = [None] * n
    frames = 0
    wall_start = time.perf_counter()
    cpu_start = time.process_time()

    for k in range(steps + 1):
        t_s = k * dt_s
        positions = np.array([local_ned_to_mission_enu(s.position_ned_m, pad) for s, pad in zip(states, pads)])
        velocities = np.array([ned_to_enu(s.velocity_ned_mps) for s in states])
        owns = [
            OwnState(position_en_m=positions[i, :2].copy(), altitude_m=float(positions[i, 2]),
                     velocity_en_mps=velocities[i, :2].copy(), has_gps=vehicles[i].has_gps)
            for i in range(n)
        ]
        radio.broadcast(k, t_s, positions, [own_broadcast(memories[i], owns[i], t_s) for i in range(n)])
        radio.deliver(t_s)
        frame_due = t_s + 1e-9 >= next_frame_t
        if frame_due:
            next_frame_t += frame_period_s * max(1, math.floor((t_s + 1e-9 - next_frame_t) / frame_period_s) + 1)
        commands = np.zeros((n, 3))
        for i, vehicle in enumerate(vehicles):
            if frame_due and (cameras == "all" or vehicle.role == ROLE_BOUNDARY):
                perceptions[i] = _perception_for(flood, t_s, positions[i], camera, seed)
                frames += 1
            command, memories[i] = control_step(vehicle.role, memories[i], owns[i], perceptions[i],
                                                radio.heard_by(i, t_s), params, t_s)
            commands[i] = command.velocity_enu_mps
        t_rec[k] = t_s
        pos_rec[k] = positions
        cmd_rec[k] = commands
        foot_rec[k] = [camera.footprint_side_m(p[2]) for p in positions]
        if encircle_time_s is None and any(memories[i].encircled for i in boundary_idx):
            encircle_time_s = t_s
            events.append((t_s, "encircling complete: the two groups' leading drones met"))
        if t_s + 1e-9 >= next_polygon_t and ring_idx:
            ring = caged_polygon(positions[ring_idx, :2],
                                 [reported_edge_points(memories[i].edge_points_en_m) for i in ring_idx])
            polygons.append(PolygonSample(t_s=t_s, ring_en_m=np.asarray(ring, dtype=float)))
            next_polygon_t += scenario.polygon_period_s
        if k < steps:
            states = [step_kinematics(states[i], enu_to_ned(commands[i]), scenario.kinematics, dt_s) for i in range(n)]
        if progress is not None:
            progress(t_s)

    wall_s = time.perf_counter() - wall_start
    cpu_s = time.process_time() - cpu_start
    events.append((steps * dt_s, f"lockstep end after {wall_s:.2f} s wall"))
    record = MissionRecord(
        scenario=scenario.name,
        mode=mode,
        engine="lockstep",
        seed=seed,
        vehicle_ids=ids,
        roles=[v.role for v in vehicles],
        t_s=t_rec,
        positions_enu_m=pos_rec,
        commands_enu_mps=cmd_rec,
        footprint_side_m=foot_rec,
        alive=np.ones((steps + 1, n), dtype=bool),
        polygons=polygons,
        encircle_time_s=encircle_time_s,
        climb_events=[m.climb_events for m in memories],
        events=events,
    )
    return LockstepResult(record, flood, params, wall_s, cpu_s, steps, frames, radio.heard_total, radio.lost_total)
