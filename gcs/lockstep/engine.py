"""One simulated clock, the whole fleet through the onboard core at once: sense, hear, decide, move (package doc).

The flood clock starts with every vehicle hovering at the nominal altitude over its pad in OFFBOARD (SPEC §4: the
flood clock starts when all are airborne): the vehicle backend's ``hover_start`` brings them there (the px4
backend flies the real arm, take-off and OFFBOARD sequence). Each control period:

1. the backend's state becomes every drone's telemetry: its autopilot's estimate (position, heading, GPS fix; the
   truth when the sensors are exact), while the radio, the camera and the record use the truth;
2. each receiver's inbox is what the in-memory radio delivers by now (range on true positions, loss, latency);
3. when a camera frame is due (``[camera] rate_hz``, the grid of :mod:`mock_autopilot.periodic_schedule`) every
   drone's frame is rendered and perceived; in between, each drone keeps its newest result, as an agent does;
4. :func:`vehicle_agents.core.onboard.onboard_step` runs for the whole fleet (N = fleet; an agent process calls the
   same function with N = 1): flight phase, neighbour table, control law, setpoints and state messages;
5. the state messages go on the radio, encoded once and decoded once; the ground station hears all of them and
   rebuilds its caged polygon from them each ``polygon_period_s`` (:func:`gcs.polygon.reports.aggregate_polygon`,
   as in the processes engine);
6. the backend applies the setpoints and flight-phase requests and advances ``1 / control_rate_hz``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from comms.frames import enu_to_geodetic, local_ned_to_mission_enu, ned_to_enu
from comms.messages import NeighbourState
from comms.radio_model import GROUND_NODE_ID, radio_model_of
from gcs.lockstep.backend_choice import BackendKind, make_backend
from gcs.polygon.radio_node import GroundNode, antenna_enu_m
from gcs.lockstep.radio_link import InMemoryRadio
from gcs.mission_record import MissionRecord, PolygonSample
from gcs.polygon.reports import aggregate_polygon, georeference_offset_en_m, report_max_age_s
from gcs.scenario import Scenario
from mission_plan.control_params import ControlMode
from mission_plan.jitter import start_delays_s
from mission_plan.roles import Role
from mock_autopilot.backends.interface import MAVSDK_MODE_NAMES, BackendState, VehicleRequest
from mock_autopilot.camera.model import CameraModel
from mission_plan.imaging import ImagingSpec, mean_wind_en_mps
from mock_autopilot.camera.body_tilt import tilt_from_acceleration_rad
from mock_autopilot.camera.render import MIN_ALTITUDE_M, CameraPose, render_frame
from mock_autopilot.periodic_schedule import next_slot_s, slot_reached
from mock_autopilot.world.config import flood_model_from_config
from mock_autopilot.world.flood_model import FloodModel
from mock_autopilot.world.ground import height_above_ground_m
from vehicle_agents.control.params import ControlParams
from vehicle_agents.control.types import ROLE_BOUNDARY, ROLE_LEADER
from vehicle_agents.core.onboard import (
    SETPOINT_ACTIONS,
    GroundOrder,
    OnboardInputs,
    OnboardPlan,
    initial_state,
    onboard_step,
)
from vehicle_agents.core.telemetry import TelemetryBatch
from vehicle_agents.flight_phase import Action, Command, Phase, PhaseLimits
from vehicle_agents.perception.result import PerceptionResult
from vehicle_agents.perception.segmentation import perceive


_REQUESTS = {
    Action.ARM: VehicleRequest.ARM,
    Action.TAKEOFF: VehicleRequest.TAKEOFF,
    Action.START_OFFBOARD: VehicleRequest.START_OFFBOARD,
    Action.HOLD: VehicleRequest.HOLD,
    Action.LAND: VehicleRequest.LAND,
}


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
    radio_bytes: int = 0
    """State-message bytes put on the air (each broadcast once)."""


def telemetry_of(state: BackendState, pads_enu_m: NDArray[np.float64], gps: NDArray[np.bool_],
                 scenario: Scenario) -> TelemetryBatch:
    """What each drone's autopilot reports: its estimate of the state, modes in MAVSDK's spelling, a GPS fix where
    fitted."""
    n = state.vehicle_count
    positions_enu_m = local_ned_to_mission_enu(state.reported_position_ned_m, pads_enu_m)
    lat = np.full(n, math.nan)
    lon = np.full(n, math.nan)
    if np.any(gps):
        fix = enu_to_geodetic(positions_enu_m[gps], scenario.home)
        lat[gps], lon[gps] = fix[:, 0], fix[:, 1]
    return TelemetryBatch(
        position_ned_m=state.reported_position_ned_m,
        velocity_ned_mps=state.velocity_ned_mps,
        yaw_ned_rad=state.reported_yaw_ned_rad,
        armed=state.armed,
        in_air=state.in_air,
        flight_mode=tuple(MAVSDK_MODE_NAMES.get(mode, mode) for mode in state.flight_mode),
        battery_fraction=state.battery_fraction,
        ready_to_arm=np.ones(n, dtype=bool),
        has_global_position=gps & state.alive,
        latitude_deg=lat,
        longitude_deg=lon,
        link_silence_s=np.where(state.alive, 0.0, math.inf),
    )


def _perception_for(
    flood: FloodModel, t_s: float, position_enu_m: NDArray[np.float64], camera: CameraModel, seed: int,
    pose: CameraPose, imaging: ImagingSpec, yaw_ned_rad: float, reported_yaw_ned_rad: float,
) -> PerceptionResult:
    """Render and perceive one frame from the body's true attitude, under the scenario's imaging conditions;
    perception scales by the downward rangefinder's height above ground, as the agent does with PX4's
    DISTANCE_SENSOR (equal to the altitude over flat ground), and projects with the attitude the autopilot reports
    (its heading estimate; roll and pitch are reported as they are). A level camera's frame is rendered heading
    north, which the ground does not tell apart, with perception off by the autopilot's heading error as an agent's
    is; a tilted one at its true heading, since the tilt is about the body's axes."""
    roll, pitch = pose.tilt_rad
    level = roll == 0.0 and pitch == 0.0
    render_yaw = 0.0 if level else yaw_ned_rad
    frame = render_frame(flood, t_s, position_enu_m, render_yaw, camera, seed, pose=pose, imaging=imaging)
    height_m = max(height_above_ground_m(flood, position_enu_m), MIN_ALTITUDE_M)
    perceive_yaw = reported_yaw_ned_rad - yaw_ned_rad + render_yaw
    return perceive(frame.image_bgr, height_m, camera.fov_deg, perceive_yaw, roll_rad=roll, pitch_rad=pitch)


@dataclass(frozen=True)
class _Trace:
    """What the record keeps of every control step: time, true positions, the setpoints sent, footprints, who flies."""

    t_s: NDArray[np.float64]
    positions_enu_m: NDArray[np.float64]
    commands_enu_mps: NDArray[np.float64]
    footprint_side_m: NDArray[np.float64]
    alive: NDArray[np.bool_]

    @classmethod
    def empty(cls, steps: int, vehicles: int) -> _Trace:
        return cls(np.zeros(steps), np.zeros((steps, vehicles, 3)), np.zeros((steps, vehicles, 3)),
                   np.zeros((steps, vehicles)), np.ones((steps, vehicles), dtype=bool))

    def add(self, k: int, t_s: float, positions_enu_m: NDArray[np.float64], setpoints_ned_mps: NDArray[np.float64],
            sent: NDArray[np.bool_], alive: NDArray[np.bool_], camera: CameraModel) -> None:
        """Step ``k``: a setpoint not sent (the drone is not in OFFBOARD flight) is recorded as zero."""
        commands_enu = ned_to_enu(setpoints_ned_mps)
        commands_enu[~sent] = 0.0
        self.t_s[k] = t_s
        self.positions_enu_m[k] = positions_enu_m
        self.commands_enu_mps[k] = commands_enu
        self.footprint_side_m[k] = [camera.footprint_side_m(p[2]) for p in positions_enu_m]
        self.alive[k] = alive


def _broadcast(radio: InMemoryRadio, ground: GroundNode | None, t_s: float, positions_enu_m: NDArray[np.float64],
               messages: Sequence[NeighbourState | None],
               gcs_heard: dict[int, NeighbourState]) -> dict[int, NeighbourState]:
    """Put the drones' state messages on the air; returns what the ground station holds now: every broadcast when it
    is outside the radio, else what reached its antenna."""
    if ground is None:
        for message in radio.broadcast(t_s, positions_enu_m, messages):
            if message is not None:
                gcs_heard[message.sender_id] = message
        return gcs_heard
    radio.broadcast(t_s, ground.with_antenna(positions_enu_m), [*messages, None])
    return dict(ground.heard)


def _onboard_plan(scenario: Scenario, params: ControlParams
                  ) -> tuple[OnboardPlan, NDArray[np.float64], NDArray[np.bool_]]:
    """The fleet's onboard plan, its pads [m; (N,3) mission ENU] and which vehicles carry GPS."""
    vehicles = scenario.vehicles
    pads = np.array([v.pad_enu_m for v in vehicles], dtype=float)
    gps = np.array([v.has_gps for v in vehicles], dtype=bool)
    plan = OnboardPlan(
        vehicle_ids=tuple(v.vehicle_id for v in vehicles), roles=tuple(v.role for v in vehicles),
        pads_en_m=tuple((float(p[0]), float(p[1])) for p in pads), has_gps=tuple(bool(g) for g in gps),
        params=params, limits=PhaseLimits(takeoff_altitude_m=scenario.altitude_m),
    )
    return plan, pads, gps


def run_lockstep(
    scenario: Scenario,
    mode: str = ControlMode.PAPER,
    seed: int | None = None,
    duration_s: float | None = None,
    control_params: ControlParams | None = None,
    progress: Callable[[float], None] | None = None,
    cameras: str = "all",
    backend: BackendKind = BackendKind.KINEMATIC,
) -> LockstepResult:
    """Run ``scenario`` in ``mode`` to ``duration_s`` (default: the scenario's) and return the record.

    ``cameras = "all"`` renders and perceives every vehicle's camera at every frame time; ``"boundary"`` only the
    boundary drones' (the only law that reads images, as the processes engine streams by default); the others then
    get no perception result.
    """
    if cameras not in ("all", Role.BOUNDARY):
        raise ValueError(f"cameras: must be all or boundary, got {cameras!r}")
    seed = scenario.seed if seed is None else seed
    duration_s = scenario.duration_s if duration_s is None else duration_s
    params = control_params if control_params is not None else scenario.control_params(mode)
    flood = flood_model_from_config(scenario.flood, seed=seed, base_dir=scenario.source_dir)
    camera = CameraModel(scenario.camera.width_px, scenario.camera.height_px, scenario.camera.fov_deg)
    vehicles = scenario.vehicles
    n = len(vehicles)
    plan, pads, gps = _onboard_plan(scenario, params)
    ids = list(plan.vehicle_ids)
    delays_s = start_delays_s(tuple(ids), scenario.start_jitter_s, seed)
    core = initial_state(plan, Phase.STANDBY if any(delays_s) else Phase.MISSION)
    started = GroundOrder(Command.START, 0.0, 0.0)
    waiting = GroundOrder(None, 0.0, 0.0)
    dt_s = 1.0 / scenario.control_rate_hz
    steps = int(math.floor(duration_s / dt_s + 1e-9))
    radio = InMemoryRadio(
        radio_model_of(scenario.radio, seed),
        [*ids, GROUND_NODE_ID] if not scenario.radio.gcs_lossless else ids,
    )
    ground = None if scenario.radio.gcs_lossless else GroundNode(antenna_enu_m(pads), scenario.control_rate_hz)
    fleet = make_backend(backend, scenario, seed)
    state = fleet.hover_start(scenario.altitude_m)
    boundary_idx = [i for i, v in enumerate(vehicles) if v.role == ROLE_BOUNDARY]
    camera_idx = [i for i, v in enumerate(vehicles) if cameras == "all" or v.role == ROLE_BOUNDARY]
    ring_order = params.ring_order()
    leader_id = next((v.vehicle_id for v in vehicles if v.role == ROLE_LEADER and v.has_gps), None)
    gcs_heard: dict[int, NeighbourState] = {}
    max_report_age_s = report_max_age_s(scenario.control_rate_hz)

    trace = _Trace.empty(steps + 1, n)
    polygons: list[PolygonSample] = []
    encircle_time_s: float | None = None
    events = [(0.0, f"lockstep start: {scenario.name}, mode {mode}, seed {seed}, {n} vehicles, backend {backend.value}")]
    next_polygon_t = next_frame_t = 0.0
    frame_period_s = 1.0 / scenario.camera.rate_hz
    perceptions: list[PerceptionResult | None] = [None] * n
    frames = 0
    wind = mean_wind_en_mps(scenario)
    previous_velocity_ned = np.array(state.velocity_ned_mps, dtype=float)
    wall_start = time.perf_counter()
    cpu_start = time.process_time()

    for k in range(steps + 1):
        t_s = k * dt_s
        positions = local_ned_to_mission_enu(state.position_ned_m, pads)
        positions[~state.alive] = np.nan
        inboxes = radio.deliver(t_s)
        if ground is not None:
            ground.hear(inboxes[n].states, t_s)
            inboxes = inboxes[:n]
        velocity_ned = np.array(state.velocity_ned_mps, dtype=float)
        tilts = (np.stack(state.tilt_rad, axis=-1) if state.roll_rad is not None
                 else tilt_from_acceleration_rad((velocity_ned - previous_velocity_ned) / dt_s, state.yaw_ned_rad))
        previous_velocity_ned = velocity_ned
        if slot_reached(next_frame_t, t_s):
            next_frame_t = next_slot_s(next_frame_t, frame_period_s, t_s)
            for i in (i for i in camera_idx if state.alive[i]):
                pose = CameraPose(tilt_rad=(float(tilts[i, 0]), float(tilts[i, 1])), vehicle_id=ids[i],
                                  velocity_en_mps=(float(velocity_ned[i, 1]), float(velocity_ned[i, 0])),
                                  wind_en_mps=wind)
                perceptions[i] = _perception_for(flood, t_s, positions[i], camera, seed, pose, scenario.imaging,
                                                 float(state.yaw_ned_rad[i]), float(state.reported_yaw_ned_rad[i]))
                frames += 1
        orders = tuple(started if t_s >= delay - 1e-9 else waiting for delay in delays_s)
        inputs = OnboardInputs(t_s=t_s, telemetry=telemetry_of(state, pads, gps, scenario),
                               perception=perceptions, inbox=inboxes, orders=orders)
        outputs, core = onboard_step(plan, core, inputs)
        gcs_heard = _broadcast(radio, ground, t_s, positions, outputs.state_messages, gcs_heard)
        sent = np.array([a in SETPOINT_ACTIONS for a in outputs.actions], dtype=bool)
        trace.add(k, t_s, positions, outputs.velocity_setpoint_ned_mps, sent, state.alive, camera)
        if encircle_time_s is None and any(core.memories[i].encircled for i in boundary_idx):
            encircle_time_s = t_s
            events.append((t_s, "encircling complete: the two groups' leading drones met"))
        if slot_reached(next_polygon_t, t_s) and ring_order:
            leader = gcs_heard.get(leader_id) if leader_id is not None else None
            ring = aggregate_polygon(gcs_heard, ring_order, georeference_offset_en_m(leader, scenario.home), t_s,
                                     max_report_age_s)
            polygons.append(PolygonSample(t_s=t_s, ring_en_m=np.asarray(ring, dtype=float)))
            next_polygon_t = next_slot_s(next_polygon_t, scenario.polygon_period_s, t_s)
        if k < steps:
            requests = [_REQUESTS.get(a, VehicleRequest.NONE) for a in outputs.actions]
            state = fleet.step(outputs.velocity_setpoint_ned_mps, outputs.yaw_ned_rad, sent, requests, dt_s)
        if progress is not None:
            progress(t_s)

    wall_s = time.perf_counter() - wall_start
    cpu_s = time.process_time() - cpu_start
    events.append((steps * dt_s, f"lockstep end after {wall_s:.2f} s wall"))
    record = MissionRecord(
        scenario=scenario.name, mode=mode, engine="lockstep", seed=seed, vehicle_ids=ids,
        roles=[v.role for v in vehicles], t_s=trace.t_s, positions_enu_m=trace.positions_enu_m,
        commands_enu_mps=trace.commands_enu_mps, footprint_side_m=trace.footprint_side_m, alive=trace.alive,
        polygons=polygons, encircle_time_s=encircle_time_s, climb_events=[m.climb_events for m in core.memories],
        events=events,
    )
    return LockstepResult(record, flood, params, wall_s, cpu_s, steps, frames, radio.heard_total, radio.lost_total,
                          radio.bytes_sent)
