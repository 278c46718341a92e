"""Whether the fleet is ready for the next mission phase, and in one line why not: pure functions of what the
GCS link shows (:class:`~gcs.processes.mavlink_watch.VehicleWatch`) and which agents reported."""

from __future__ import annotations

from collections.abc import Collection, Container, Mapping, Sequence
from typing import TYPE_CHECKING

from comms.px4 import Px4Mode
from gcs.processes.mavlink_watch import VehicleWatch

if TYPE_CHECKING:
    from gcs.processes.mission_children import MissionChildren

OFFBOARD = Px4Mode.OFFBOARD.value

VEHICLE_LOST_AFTER_S = 2.0
"""Wall seconds without a heartbeat on the GCS link before a vehicle is reported lost (SPEC §7: within 2 s)."""


def vehicle_lost_after_s(speed: float) -> float:
    """Heartbeat silence [wall s] that counts as a lost vehicle at simulation speed ``speed``: two heartbeat
    periods. The mock PX4 beats at 1 Hz of simulated time, so below real time (``--speed`` < 1) its heartbeats
    come further apart on the wall clock and the bound widens with them; at or above real time it stays at SPEC
    §7's 2 s."""
    return VEHICLE_LOST_AFTER_S / min(1.0, speed)


class HeartbeatWatch:
    """Which vehicles fell silent on the GCS link (and came back), announced once per change."""

    def __init__(self, speed: float) -> None:
        self.lost_after_s = vehicle_lost_after_s(speed)
        self.silent: set[int] = set()

    def changes(self, vehicle_ids: Sequence[int], watched: Mapping[int, VehicleWatch],
                now_wall_s: float) -> list[tuple[int, bool, float]]:
        """(vehicle id, now silent, silence bound [s]) for every vehicle whose silence changed since the last call."""
        out = []
        for vid in vehicle_ids:
            watch = watched.get(vid)
            silent = watch is not None and watch.heartbeat_age_s(now_wall_s) > self.lost_after_s
            if silent != (vid in self.silent):
                (self.silent.add if silent else self.silent.discard)(vid)
                out.append((vid, silent, self.lost_after_s))
        return out


def everyone_heard(vehicle_ids: Sequence[int], watched: Mapping[int, VehicleWatch]) -> bool:
    """Every vehicle's heartbeat arrived on the GCS link."""
    return all(vid in watched and watched[vid].last_heartbeat_monotonic_s for vid in vehicle_ids)


def everyone_in_offboard(vehicle_ids: Sequence[int], lost: Collection[int], watched: Mapping[int, VehicleWatch],
                         floor_m: float) -> bool:
    """Every vehicle not lost is armed, in OFFBOARD and at least ``floor_m`` up."""
    for vid in vehicle_ids:
        if vid in lost:
            continue
        watch = watched.get(vid)
        if watch is None or watch.mode != OFFBOARD or not watch.armed or not watch.altitude_m >= floor_m:
            return False
    return True


def takeoff_problem(watched: Mapping[int, VehicleWatch], lost: Collection[int], takeoff_timeout_s: float) -> str:
    """The vehicles still not airborne in OFFBOARD, with what the GCS link shows of them (six at most)."""
    late = [f"{vid} ({w.mode}, {'armed' if w.armed else 'disarmed'}, {w.altitude_m:.1f} m)"
            for vid, w in sorted(watched.items())
            if vid not in lost and (w.mode != OFFBOARD or not w.armed)]
    return f"vehicles not airborne in OFFBOARD after {takeoff_timeout_s:g} s: {', '.join(late[:6])}"


def startup_problem(vehicle_ids: Sequence[int], watched: Mapping[int, VehicleWatch], reported: Container[int],
                    agent_alive: Mapping[int, bool], children: MissionChildren | None, *, truth_missing: bool,
                    gcs_port: int, timeout_s: float, connected: int) -> str:
    """Why start-up stalled: vehicles silent on the GCS link, agents not started or not reporting over Zenoh (with
    the last lines of their logs when the station started them), no ground truth."""
    silent = [vid for vid in vehicle_ids if vid not in watched]
    no_agent = [vid for vid in vehicle_ids if not agent_alive.get(vid) or vid not in reported]
    parts = []
    if silent:
        tail = f": {children.services['sim'].log_tail(2)}" if children is not None else ""
        parts.append(f"no MAVLink from vehicles {silent} on GCS port {gcs_port}{tail}")
    if children is not None and children.to_start:
        parts.append(f"{len(children.to_start)} agents not started yet (the ones before them were still connecting)")
    started_silent = [vid for vid in no_agent if children is None or vid in children.agents]
    if started_silent:
        tail = f": {children.agents[started_silent[0]].log_tail(2)}" if children is not None else ""
        parts.append(f"agents {started_silent} did not report over Zenoh{tail}")
    if truth_missing:
        parts.append("no ground truth from the simulator bridge")
    return (f"start-up stalled: nothing came up for {timeout_s:g} s ({connected} of {len(vehicle_ids)} agents "
            f"connected): " + "; ".join(parts))
