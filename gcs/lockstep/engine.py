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
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from comms.frames import enu_to_geodetic, local_ned_to_mission_enu, ned_to_enu
from comms.messages import NeighbourState
from comms.radio_model import GROUND_NODE_ID, radio_model_of
from gcs.lockstep.backend_choice import BackendKind, make_backend
from gcs.polygon.radio_node import GroundNode, antenna_enu_m
from gcs.lockstep.radio_link import InMemoryRadio
from gcs.lockstep.ranging import LockstepRanging
from gcs.mission_record import MissionRecord, PolygonSample
from gcs.polygon.report_window import ReportHistory, remembered
from gcs.polygon.reports import aggregate_polygon, georeference_offset_en_m, report_max_age_s
from gcs.relay_refusals import refused_copies_line
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


_STARTED = GroundOrder(Command.START, 0.0, 0.0)
_WAITING = GroundOrder(None, 0.0, 0.0)
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


@dataclass
class _Cameras:
    """The fleet's cameras: who carries one, when the next frame is due (``[camera] rate_hz``), and each drone's newest
    perception result, which it keeps between frames as an agent does."""

    flood: FloodModel
    model: CameraModel
    scenario: Scenario
    seed: int
    carriers: list[int]
    perceptions: list[PerceptionResult | None]
    next_frame_t_s: float = 0.0
    frames: int = 0

    def capture(self, t_s: float, state: BackendState, positions_enu_m: NDArray[np.float64],
                velocity_ned_mps: NDArray[np.float64], tilts_rad: NDArray[np.float64]) -> None:
        """Render and perceive every living carrier's frame when one is due."""
        if not slot_reached(self.next_frame_t_s, t_s):
            return
        self.next_frame_t_s = next_slot_s(self.next_frame_t_s, 1.0 / self.scenario.camera.rate_hz, t_s)
        wind = mean_wind_en_mps(self.scenario)
        for i in (i for i in self.carriers if state.alive[i]):
            pose = CameraPose(tilt_rad=(float(tilts_rad[i, 0]), float(tilts_rad[i, 1])),
                              vehicle_id=self.scenario.vehicles[i].vehicle_id,
                              velocity_en_mps=(float(velocity_ned_mps[i, 1]), float(velocity_ned_mps[i, 0])),
                              wind_en_mps=wind)
            self.perceptions[i] = _perception_for(self.flood, t_s, positions_enu_m[i], self.model, self.seed, pose,
                                                  self.scenario.imaging, float(state.yaw_ned_rad[i]),
                                                  float(state.reported_yaw_ned_rad[i]))
            self.frames += 1


@dataclass
class _GroundPolygon:
    """The ground station's caged polygon, rebuilt every ``polygon_period_s`` from the states it holds, georeferenced
    by the leader's GPS report as in the processes engine."""

    scenario: Scenario
    ring_order: list[int]
    leader_id: int | None
    max_report_age_s: float
    samples: list[PolygonSample]
    next_t_s: float = 0.0
    history: ReportHistory = field(default_factory=dict)

    def sample(self, t_s: float, heard: dict[int, NeighbourState]) -> None:
        """Keep the boundary reports of the last half second; rebuild the polygon when its period has come."""
        self.history = remembered(self.history, heard, self.ring_order, t_s)
        if not (slot_reached(self.next_t_s, t_s) and self.ring_order):
            return
        leader = heard.get(self.leader_id) if self.leader_id is not None else None
        ring = aggregate_polygon(heard, self.ring_order, georeference_offset_en_m(leader, self.scenario.home), t_s,
                                 self.max_report_age_s, self.history)
        self.samples.append(PolygonSample(t_s=t_s, ring_en_m=np.asarray(ring, dtype=float)))
        self.next_t_s = next_slot_s(self.next_t_s, self.scenario.polygon_period_s, t_s)


class _LockstepRun:
    """One run's world and its progress: the fleet's backend, the onboard core, the radio, the cameras, the ground
    station's polygon and the trace, advanced one control step at a time by :meth:`step`."""

    def __init__(self, scenario: Scenario, mode: str, seed: int, params: ControlParams, cameras: str,
                 backend: BackendKind, steps: int) -> None:
        self.scenario, self.mode, self.seed, self.params, self.backend = scenario, mode, seed, params, backend
        self.flood = flood_model_from_config(scenario.flood, seed=seed, base_dir=scenario.source_dir)
        vehicles = scenario.vehicles
        self.plan, self.pads, self.gps = _onboard_plan(scenario, params)
        self.ids = list(self.plan.vehicle_ids)
        self.delays_s = start_delays_s(tuple(self.ids), scenario.start_jitter_s, seed)
        self.core = initial_state(self.plan, Phase.STANDBY if any(self.delays_s) else Phase.MISSION)
        self.dt_s = 1.0 / scenario.control_rate_hz
        self.radio = InMemoryRadio(
            radio_model_of(scenario.radio, seed),
            [*self.ids, GROUND_NODE_ID] if not scenario.radio.gcs_lossless else self.ids,
        )
        self.ground = None if scenario.radio.gcs_lossless else GroundNode(antenna_enu_m(self.pads),
                                                                                     scenario.control_rate_hz)
        self.fleet = make_backend(backend, scenario, seed)
        self.state = self.fleet.hover_start(scenario.altitude_m)
        self.boundary_idx = [i for i, v in enumerate(vehicles) if v.role == ROLE_BOUNDARY]
        self.cameras = _Cameras(
            self.flood, CameraModel(scenario.camera.width_px, scenario.camera.height_px, scenario.camera.fov_deg),
            scenario, seed, [i for i, v in enumerate(vehicles) if cameras == "all" or v.role == ROLE_BOUNDARY],
            [None] * len(vehicles))
        self.ranging = LockstepRanging.of_fleet(self.ids, self.gps, scenario.sensors, params, seed)
        self.polygon = _GroundPolygon(
            scenario, params.ring_order(),
            next((v.vehicle_id for v in vehicles if v.role == ROLE_LEADER and v.has_gps), None),
            report_max_age_s(scenario.control_rate_hz), [])
        self.gcs_heard: dict[int, NeighbourState] = {}
        self.trace = _Trace.empty(steps + 1, len(vehicles))
        self.encircle_time_s: float | None = None
        self.events = [(0.0, f"lockstep start: {scenario.name}, mode {mode}, seed {seed}, {len(vehicles)} vehicles, "
                             f"backend {backend.value}")]
        self.previous_velocity_ned = np.array(self.state.velocity_ned_mps, dtype=float)

    def _tilts_rad(self, velocity_ned_mps: NDArray[np.float64]) -> NDArray[np.float64]:
        """The bodies' (roll, pitch): the backend's own where it models attitude, else from the acceleration."""
        state = self.state
        if state.roll_rad is not None:
            return np.stack(state.tilt_rad, axis=-1)
        acceleration = (velocity_ned_mps - self.previous_velocity_ned) / self.dt_s
        return tilt_from_acceleration_rad(acceleration, state.yaw_ned_rad)

    def step(self, k: int, last: bool) -> None:
        """Control step ``k`` (numbered steps 1-6 in the module doc); the backend moves unless it is the ``last``."""
        t_s = k * self.dt_s
        state, n = self.state, len(self.ids)
        positions = local_ned_to_mission_enu(state.position_ned_m, self.pads)
        positions[~state.alive] = np.nan
        inboxes = self.radio.deliver(t_s)
        if self.ground is not None:
            self.ground.hear(inboxes[n].states, t_s)
            inboxes = inboxes[:n]
        velocity_ned = np.array(state.velocity_ned_mps, dtype=float)
        tilts = self._tilts_rad(velocity_ned)
        self.previous_velocity_ned = velocity_ned
        self.cameras.capture(t_s, state, positions, velocity_ned, tilts)
        self.ranging.measure(t_s, positions, state.yaw_ned_rad, state.alive)
        orders = tuple(_STARTED if t_s >= delay - 1e-9 else _WAITING for delay in self.delays_s)
        inputs = OnboardInputs(t_s=t_s, telemetry=telemetry_of(state, self.pads, self.gps, self.scenario),
                               perception=self.cameras.perceptions, inbox=inboxes, orders=orders,
                               ranging=self.ranging.latest)
        outputs, self.core = onboard_step(self.plan, self.core, inputs)
        self.gcs_heard = _broadcast(self.radio, self.ground, t_s, positions, outputs.state_messages, self.gcs_heard)
        sent = np.array([a in SETPOINT_ACTIONS for a in outputs.actions], dtype=bool)
        self.trace.add(k, t_s, positions, outputs.velocity_setpoint_ned_mps, sent, state.alive, self.cameras.model)
        if self.encircle_time_s is None and any(self.core.memories[i].encircled for i in self.boundary_idx):
            self.encircle_time_s = t_s
            self.events.append((t_s, "encircling complete: the two groups' leading drones met"))
        self.polygon.sample(t_s, self.gcs_heard)
        if not last:
            requests = [_REQUESTS.get(a, VehicleRequest.NONE) for a in outputs.actions]
            self.state = self.fleet.step(outputs.velocity_setpoint_ned_mps, outputs.yaw_ned_rad, sent, requests,
                                         self.dt_s)

    def result(self, steps: int, wall_s: float, cpu_s: float) -> LockstepResult:
        refused = list(self.core.refused_copies) or [0] * len(self.ids)
        ground_refused = None if self.ground is None else self.ground.refused_copies
        self.events.append((steps * self.dt_s, refused_copies_line(self.ids, refused, ground_refused)))
        self.events.append((steps * self.dt_s, f"lockstep end after {wall_s:.2f} s wall"))
        trace, vehicles = self.trace, self.scenario.vehicles
        record = MissionRecord(
            scenario=self.scenario.name, mode=self.mode, engine="lockstep", seed=self.seed, vehicle_ids=self.ids,
            roles=[v.role for v in vehicles], t_s=trace.t_s, positions_enu_m=trace.positions_enu_m,
            commands_enu_mps=trace.commands_enu_mps, footprint_side_m=trace.footprint_side_m, alive=trace.alive,
            polygons=self.polygon.samples, encircle_time_s=self.encircle_time_s,
            climb_events=[m.climb_events for m in self.core.memories], events=self.events,
            refused_copies=refused, ground_refused_copies=ground_refused,
        )
        return LockstepResult(record, self.flood, self.params, wall_s, cpu_s, steps, self.cameras.frames,
                              self.radio.heard_total, self.radio.lost_total, self.radio.bytes_sent)


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
    steps = int(math.floor(duration_s / (1.0 / scenario.control_rate_hz) + 1e-9))
    run = _LockstepRun(scenario, mode, seed, params, cameras, backend, steps)
    wall_start = time.perf_counter()
    cpu_start = time.process_time()
    for k in range(steps + 1):
        run.step(k, last=k == steps)
        if progress is not None:
            progress(k * run.dt_s)
    return run.result(steps, time.perf_counter() - wall_start, time.process_time() - cpu_start)
