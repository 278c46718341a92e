"""The simulator's side of the companion-computer link: camera frames and ground truth over Zenoh.

A real drone's companion computer gets video from its own camera; here the mock fleet owns the world, so this
bridge renders each airborne vehicle's downward camera (:func:`mock_autopilot.camera.render.render_frame`) from
the fleet's TRUE state and publishes it on that vehicle's camera key, like a video stream. It also publishes the
whole fleet's ground truth, which feeds the radio emulator (range is decided on true positions) and the ground station's
evaluation. Nothing here is seen by the agents except their own camera frames.

The flood clock (SPEC §4) starts when every vehicle is airborne in OFFBOARD; the ground station sees that on the
MAVLink GCS link and says so in its ``MissionCommand`` (``flood_clock_start_t_s``), which this bridge follows, so the
flood the cameras see and the flood the metrics use share one clock. Everything is stamped with mission time,
the fleet's simulation clock.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from comms.keys import MissionKeys
from comms.messages import CameraFrame, GroundTruth, MissionCommand, decode, encode
from comms.signing import unsigned_body
from comms.zenoh_session import ZenohSession
from mission_plan.roles import Role
from mock_autopilot.camera.model import CameraModel
from mission_plan.imaging import ImagingSpec
from mock_autopilot.camera.render import MIN_ALTITUDE_M, CameraPose, render_frame
from mock_autopilot.periodic_schedule import next_slot_s, slot_reached
from mock_autopilot.world.flood_model import FloodModel
from mock_autopilot.world.ground import height_above_ground_m

MIN_CAMERA_ALTITUDE_M = 1.0
"""Below this the camera sees only the pad: no frames are sent (a real companion computer would send them, but no
control law uses them on the ground)."""


@dataclass(frozen=True)
class VehicleTruth:
    """One vehicle's true state [m, m/s; mission ENU] and PX4 yaw [rad; NED]; ``alive`` False once killed."""

    vehicle_id: int
    position_enu_m: NDArray[np.float64]
    velocity_enu_mps: NDArray[np.float64]
    yaw_ned_rad: float
    alive: bool = True
    tilt_rad: tuple[float, float] = (0.0, 0.0)
    """Body (roll, pitch) [rad]: the camera is fixed to the body."""


def ground_truth_message(t_s: float, vehicles: Sequence[VehicleTruth]) -> GroundTruth:
    return GroundTruth(
        t_s=float(t_s),
        vehicle_ids=[v.vehicle_id for v in vehicles],
        positions_enu_m=[tuple(float(c) for c in v.position_enu_m) for v in vehicles],  # type: ignore[misc]
        velocities_enu_mps=[tuple(float(c) for c in v.velocity_enu_mps) for v in vehicles],  # type: ignore[misc]
        yaw_ned_rad=[float(v.yaw_ned_rad) for v in vehicles],
        alive=[bool(v.alive) for v in vehicles],
        tilt_rad=[(float(v.tilt_rad[0]), float(v.tilt_rad[1])) for v in vehicles],
    )


def camera_frame_message(
    vehicle: VehicleTruth, seq: int, t_s: float, flood: FloodModel, flood_t_s: float, camera: CameraModel, seed: int,
    imaging: ImagingSpec = ImagingSpec(), wind_en_mps: tuple[float, float] = (0.0, 0.0),
) -> CameraFrame:
    """Render one vehicle's downward view at flood time ``flood_t_s`` from its true attitude, under the imaging
    conditions, and wrap it as raw BGR (no codec cost)."""
    pose = CameraPose(tilt_rad=vehicle.tilt_rad, vehicle_id=vehicle.vehicle_id,
                      velocity_en_mps=(float(vehicle.velocity_enu_mps[0]), float(vehicle.velocity_enu_mps[1])),
                      wind_en_mps=wind_en_mps)
    frame = render_frame(flood, flood_t_s, vehicle.position_enu_m, vehicle.yaw_ned_rad, camera, seed, pose=pose,
                         imaging=imaging)
    image = np.ascontiguousarray(frame.image_bgr, dtype=np.uint8)
    return CameraFrame(
        vehicle_id=vehicle.vehicle_id,
        seq=seq,
        t_s=float(t_s),
        altitude_m=max(height_above_ground_m(flood, vehicle.position_enu_m), MIN_ALTITUDE_M),
        yaw_ned_rad=float(vehicle.yaw_ned_rad),
        fov_deg=camera.fov_deg,
        width_px=image.shape[1],
        height_px=image.shape[0],
        encoding="raw_bgr",
        image=image.tobytes(),
    )


CAMERA_ROLES = (Role.BOUNDARY,)
"""Roles whose control law looks at the camera: only the boundary drones' (eqs 4-8, Algorithm 1). The leader (eq 9)
and the followers (eq 10) fly on radio messages alone, so streaming their video would only burn CPU; the coverage
metric uses their true footprints either way."""


def camera_users(roles: dict[int, str], which: str = Role.BOUNDARY) -> set[int] | None:
    """Vehicle ids whose camera is streamed: ``"boundary"`` (the roles in :data:`CAMERA_ROLES`) or ``"all"``."""
    if which == "all":
        return None
    if which != Role.BOUNDARY:
        raise ValueError(f"--cameras {which!r}: use boundary or all")
    return {vid for vid, role in roles.items() if role in CAMERA_ROLES}


class CameraStreamer:
    """Renders and publishes the camera frames of the vehicles in ``camera_vehicle_ids`` (None: all) every
    ``camera_period_s`` of mission time, on the flood clock the ground station's command starts.

    It runs inside the fleet's process (:class:`SimBridge`) or in a process of its own fed by the published ground
    truth (``python -m mock_autopilot.sim_bridge.cameras``): rendering then gets its own CPU and interpreter lock
    instead of competing with the fleet's MAVLink thread.
    """

    def __init__(
        self,
        session: ZenohSession,
        mission: str,
        flood: FloodModel,
        camera: CameraModel,
        seed: int,
        camera_period_s: float,
        camera_vehicle_ids: set[int] | None = None,
        on_flood_start: Callable[[float], None] | None = None,
        imaging: ImagingSpec = ImagingSpec(),
        wind_en_mps: tuple[float, float] = (0.0, 0.0),
    ) -> None:
        self.session = session
        self.keys = MissionKeys(mission)
        self.flood = flood
        self.camera = camera
        self.seed = seed
        self.camera_period_s = camera_period_s
        self.camera_vehicle_ids = camera_vehicle_ids
        self.imaging = imaging
        self.wind_en_mps = wind_en_mps
        self.flood_clock_start_s: float | None = None
        self._on_flood_start = on_flood_start
        self._commands = session.subscribe(self.keys.command)
        self._next_camera_s = 0.0
        self._frame_seq: dict[int, int] = {}
        self._last_t_s: float | None = None
        self.frames_sent = 0
        self.render_wall_s = 0.0
        self.render_cpu_s = 0.0
        self.publish_wall_s = 0.0
        self.airborne_vehicle_s = 0.0
        """Mission seconds summed over airborne camera vehicles: frames_sent / airborne_vehicle_s = frame rate."""

    def flood_time_s(self, now_s: float) -> float:
        """Flood clock: 0 until the ground station starts it, then mission time since the start."""
        return 0.0 if self.flood_clock_start_s is None else max(0.0, now_s - self.flood_clock_start_s)

    def follow_commands(self) -> None:
        """The flood clock's start from the ground station's command. The simulated world holds no mission key
        (it has no counterpart on a real mission), so it reads the command without checking its tag."""
        for item in self._commands.drain():
            msg = decode(MissionCommand, unsigned_body(item.payload))
            if msg is not None and msg.flood_clock_start_t_s is not None and self.flood_clock_start_s is None:
                self.flood_clock_start_s = msg.flood_clock_start_t_s
                if self._on_flood_start is not None:
                    self._on_flood_start(msg.flood_clock_start_t_s)

    def _streams(self, vehicle: VehicleTruth) -> bool:
        return (vehicle.alive and vehicle.position_enu_m[2] >= MIN_CAMERA_ALTITUDE_M
                and (self.camera_vehicle_ids is None or vehicle.vehicle_id in self.camera_vehicle_ids))

    def stream(self, now_s: float, vehicles: Sequence[VehicleTruth]) -> None:
        """Render and publish every streaming vehicle's frame if one is due at mission time ``now_s``."""
        self.follow_commands()
        if self._last_t_s is not None:
            airborne = sum(1 for v in vehicles if self._streams(v))
            self.airborne_vehicle_s += airborne * max(0.0, now_s - self._last_t_s)
        self._last_t_s = now_s
        if not slot_reached(self._next_camera_s, now_s):
            return
        flood_t_s = self.flood_time_s(now_s)
        for vehicle in vehicles:
            if not self._streams(vehicle):
                continue
            seq = self._frame_seq.get(vehicle.vehicle_id, 0) + 1
            self._frame_seq[vehicle.vehicle_id] = seq
            started, cpu_started = time.perf_counter(), time.thread_time()
            msg = camera_frame_message(vehicle, seq, now_s, self.flood, flood_t_s, self.camera, self.seed,
                                       self.imaging, self.wind_en_mps)
            self.render_cpu_s += time.thread_time() - cpu_started
            rendered = time.perf_counter()
            self.session.put(self.keys.camera(vehicle.vehicle_id), encode(msg))
            self.render_wall_s += rendered - started
            self.publish_wall_s += time.perf_counter() - rendered
            self.frames_sent += 1
        self._next_camera_s = next_slot_s(self._next_camera_s, self.camera_period_s, now_s)

    def frame_rate_hz(self) -> float:
        """Achieved camera frames per airborne vehicle per mission second (nominal: 1 / camera_period_s)."""
        return self.frames_sent / self.airborne_vehicle_s if self.airborne_vehicle_s > 0 else float("nan")

    def next_due_s(self) -> float:
        return self._next_camera_s

    def summary(self) -> str:
        """One line for the process's exit log: frames, achieved against nominal frame rate, where the time went."""
        return (f"sent {self.frames_sent} frames; camera frame rate {self.frame_rate_hz():.2f} Hz per airborne vehicle "
                f"(nominal {1.0 / self.camera_period_s:.2f} Hz, mission time); rendering {self.render_wall_s:.1f} s "
                f"wall ({self.render_cpu_s:.1f} s CPU), publishing {self.publish_wall_s:.1f} s wall")


class SimBridge:
    """The fleet process's side: ground truth every ``truth_period_s`` (mission seconds) and, unless the cameras
    run in their own process (``cameras=None``), the camera frames through a :class:`CameraStreamer`."""

    def __init__(self, session: ZenohSession, mission: str, truth_period_s: float,
                 cameras: CameraStreamer | None = None) -> None:
        self.session = session
        self.keys = MissionKeys(mission)
        self.truth_period_s = truth_period_s
        self.cameras = cameras
        self._next_truth_s = 0.0
        self.truths_sent = 0
        session.declare_alive(self.keys.alive("sim"))

    def tick(self, now_s: float, vehicles: Sequence[VehicleTruth]) -> None:
        """Publish whatever is due at mission time ``now_s`` (call often; it keeps its own schedule)."""
        if now_s >= self._next_truth_s:
            self.publish_truth(now_s, vehicles)
            self._next_truth_s = next_slot_s(self._next_truth_s, self.truth_period_s, now_s)
        if self.cameras is not None:
            self.cameras.stream(now_s, vehicles)

    def publish_truth(self, t_s: float, vehicles: Sequence[VehicleTruth]) -> None:
        """The truth at mission time ``t_s`` now (a paced clock publishes one per control tick, when it asks)."""
        self.session.put(self.keys.truth, encode(ground_truth_message(t_s, vehicles)))
        self.truths_sent += 1

    def next_due_s(self) -> float:
        return min(self._next_truth_s, self.cameras.next_due_s()) if self.cameras is not None else self._next_truth_s


def vehicles_from_truth(truth: GroundTruth) -> list[VehicleTruth]:
    """The per-vehicle view of a published ``GroundTruth`` (what a camera process renders from)."""
    n = len(truth.vehicle_ids)
    velocities = truth.velocities_enu_mps or [(0.0, 0.0, 0.0)] * n
    yaws = truth.yaw_ned_rad or [0.0] * n
    alive = truth.alive or [True] * n
    tilts = truth.tilt_rad or [(0.0, 0.0)] * n
    return [
        VehicleTruth(vid, np.asarray(truth.positions_enu_m[i], dtype=float), np.asarray(velocities[i], dtype=float),
                     float(yaws[i]), bool(alive[i]), (float(tilts[i][0]), float(tilts[i][1])))
        for i, vid in enumerate(truth.vehicle_ids)
    ]
