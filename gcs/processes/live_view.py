"""The ground station's live terminal view (rich): phase, clocks, every vehicle, caging, IoU, coverage, events.

The mission loop fills a :class:`MissionSnapshot` a few times a second; :func:`render` turns it into a rich
renderable and is pure (tests render it to text). When the output is not a terminal the view prints one short
status line every few seconds instead, so logs of CI runs stay readable.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from rich.console import Console, Group, RenderableType
from rich.live import Live
from rich.panel import Panel
from rich.progress_bar import ProgressBar
from rich.table import Table
from rich.text import Text

from comms.messages import FLAG_SEES_EDGE, NeighbourState
from gcs.processes.mavlink_watch import VehicleWatch
from mission_plan.roles import Role

if TYPE_CHECKING:
    from gcs.processes.ground_station import GroundStation
    from gcs.processes.mavlink_watch import MavlinkWatcher


@dataclass(frozen=True)
class VehicleRow:
    vehicle_id: int
    role: str
    group: str
    mode: str
    armed: bool
    altitude_m: float
    heartbeat_age_s: float
    """Wall seconds since the vehicle's last MAVLink heartbeat on the GCS link."""
    agent_alive: bool
    state_age_s: float
    """Mission seconds since the agent's last state message on Zenoh."""
    battery_fraction: float
    sees_edge: bool


def vehicle_rows(vehicle_ids: Sequence[int], roles: Mapping[int, str], groups: Mapping[int, str],
                 watched: Mapping[int, VehicleWatch], states: Mapping[int, NeighbourState],
                 agent_alive: Mapping[int, bool], mission_t_s: float, now_wall_s: float) -> tuple[VehicleRow, ...]:
    """One row per vehicle from what the GCS link shows and what its agent last said."""
    rows = []
    for vid in vehicle_ids:
        watch = watched.get(vid)
        state = states.get(vid)
        rows.append(VehicleRow(
            vehicle_id=vid, role=roles[vid], group=groups[vid],
            mode=watch.mode if watch else "-", armed=bool(watch and watch.armed),
            altitude_m=watch.altitude_m if watch else math.nan,
            heartbeat_age_s=watch.heartbeat_age_s(now_wall_s) if watch else math.inf,
            agent_alive=agent_alive.get(vid, False),
            state_age_s=mission_t_s - state.t_s if state else math.inf,
            battery_fraction=watch.battery_fraction if watch else math.nan,
            sees_edge=bool(state and state.has(FLAG_SEES_EDGE)),
        ))
    return tuple(rows)


@dataclass(frozen=True)
class MissionSnapshot:
    scenario: str
    mode: str
    phase: str
    mission_t_s: float
    flood_t_s: float | None
    duration_s: float
    speed: float
    vehicles: tuple[VehicleRow, ...]
    encircled: int = 0
    boundary_count: int = 0
    encircle_time_s: float | None = None
    polygon_iou: float = float("nan")
    coverage: float = float("nan")
    polygon_area_m2: float = float("nan")
    events: tuple[str, ...] = field(default_factory=tuple)
    clock: str = "free"
    real_time_factor: float = float("nan")
    """Mission seconds per wall second achieved over the last report period (the simulator's pace report)."""


def station_snapshot(station: GroundStation, watcher: MavlinkWatcher, now_wall_s: float) -> MissionSnapshot:
    """What the view shows of the ground station right now."""
    rows = vehicle_rows(station.vehicle_ids, station.roles, station.groups, watcher.vehicles, station.states,
                        station.agent_alive, station.mission_t_s, now_wall_s)
    boundary = [vid for vid in station.vehicle_ids if station.roles[vid] == Role.BOUNDARY]
    evaluation, pace = station.evaluation, station.pace.pace_report
    return MissionSnapshot(
        scenario=station.scenario.name, mode=station.options.mode, phase=station.phase.value,
        mission_t_s=station.mission_t_s, duration_s=station.duration_s,
        flood_t_s=None if station.flood_clock_start_s is None else station.flood_time_s(),
        speed=station.options.speed, vehicles=rows, boundary_count=len(boundary),
        encircled=sum(1 for vid in boundary if vid in station.states and station.states[vid].encircle_complete),
        encircle_time_s=station.recorder.encircle_time_s, polygon_area_m2=station.polygon.area_m2,
        polygon_iou=evaluation.polygon_iou if evaluation else math.nan,
        coverage=evaluation.coverage if evaluation else math.nan, events=tuple(station.events.recent),
        clock=station.options.clock, real_time_factor=pace.recent_real_time_factor if pace else math.nan,
    )


def _fmt(value: float, spec: str, missing: str = "-") -> str:
    return format(value, spec) if math.isfinite(value) else missing


def _link_text(row: VehicleRow) -> Text:
    if row.heartbeat_age_s > 3.0:
        return Text("vehicle lost", style="bold red")
    if not row.agent_alive:
        return Text("agent gone", style="bold red")
    if row.state_age_s > 1.0:
        return Text(f"stale {row.state_age_s:.1f}s", style="yellow")
    return Text("ok", style="green")


def render(snapshot: MissionSnapshot) -> RenderableType:
    """The whole view as one rich renderable."""
    flood = "not started" if snapshot.flood_t_s is None else f"{snapshot.flood_t_s:5.1f} / {snapshot.duration_s:.0f} s"
    caging = (
        f"ring closed at {snapshot.encircle_time_s:.1f} s"
        if snapshot.encircle_time_s is not None
        else f"encircling: {snapshot.encircled}/{snapshot.boundary_count} boundary drones report the ring closed"
    )
    header = Text.assemble(
        (f"{snapshot.scenario} ", "bold"),
        (f"[{snapshot.mode}] ", "cyan"),
        (f"phase {snapshot.phase}  ", "bold magenta"),
        f"mission time {snapshot.mission_t_s:6.1f} s  flood clock {flood}  speed x{snapshot.speed:g} "
        f"({snapshot.clock} clock, achieved {_fmt(snapshot.real_time_factor, '.2f')}x)\n",
        f"{caging}   polygon IoU {_fmt(snapshot.polygon_iou, '.3f')}   coverage {_fmt(snapshot.coverage, '.3f')}   "
        f"polygon area {_fmt(snapshot.polygon_area_m2, '.0f')} m²",
    )
    table = Table(expand=True, box=None, pad_edge=False)
    for column in ("id", "role", "mode", "armed", "alt m", "battery", "edge", "link"):
        table.add_column(column)
    for row in snapshot.vehicles:
        role = row.role + (f" {row.group}" if row.group else "")
        table.add_row(
            str(row.vehicle_id),
            role,
            row.mode,
            "yes" if row.armed else "no",
            _fmt(row.altitude_m, ".1f"),
            _fmt(row.battery_fraction * 100.0, ".0f") + ("%" if math.isfinite(row.battery_fraction) else ""),
            "yes" if row.sees_edge else "",
            _link_text(row),
        )
    done = snapshot.flood_t_s or 0.0
    bar = ProgressBar(total=max(snapshot.duration_s, 1e-9), completed=min(done, snapshot.duration_s))
    events = Text("\n".join(snapshot.events[-6:]), style="dim")
    return Panel(Group(header, bar, table, events), title="FloodWatch ground station", border_style="blue")


def status_line(snapshot: MissionSnapshot) -> str:
    """One plain line for non-terminal output."""
    flood = "-" if snapshot.flood_t_s is None else f"{snapshot.flood_t_s:.1f}"
    modes: dict[str, int] = {}
    for row in snapshot.vehicles:
        modes[row.mode] = modes.get(row.mode, 0) + 1
    mode_text = ", ".join(f"{n} {m}" for m, n in sorted(modes.items()))
    return (
        f"[{snapshot.phase}] t={snapshot.mission_t_s:.1f}s flood={flood}s "
        f"x{_fmt(snapshot.real_time_factor, '.2f')} {snapshot.clock} encircled={snapshot.encircled}/"
        f"{snapshot.boundary_count} IoU={_fmt(snapshot.polygon_iou, '.3f')} coverage={_fmt(snapshot.coverage, '.3f')} "
        f"vehicles: {mode_text}"
    )


class LiveOutput:
    """Where the snapshots go: a rich live view on a terminal, else one status line every few seconds."""

    def __init__(self, console: Console, live: bool, view_period_s: float = 0.25, status_period_s: float = 5.0) -> None:
        self.console = console
        self.view_period_s, self.status_period_s = view_period_s, status_period_s
        self._live = Live(console=console, refresh_per_second=4, transient=False) if live and console.is_terminal else None
        self._next_view_s = 0.0
        self._next_status_s = time.monotonic() + status_period_s

    def __enter__(self) -> LiveOutput:
        if self._live is not None:
            self._live.start()
        return self

    def __exit__(self, *exc: object) -> None:
        if self._live is not None:
            self._live.stop()

    def due(self, now_wall_s: float) -> bool:
        """Whether a new snapshot is wanted now (a few times a second)."""
        return now_wall_s >= self._next_view_s

    def show(self, snapshot: MissionSnapshot, now_wall_s: float) -> None:
        self._next_view_s = now_wall_s + self.view_period_s
        if self._live is not None:
            self._live.update(render(snapshot))
        elif now_wall_s >= self._next_status_s:
            print(status_line(snapshot), flush=True)
            self._next_status_s = now_wall_s + self.status_period_s
