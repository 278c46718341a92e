"""The simulator's health as the ground station hears it: the fleet's pace report (real-time factor, who the paced
clock left behind) and the cameras' frame statistics, the inputs of the engine verdict
(:func:`gcs.processes.run_verdict.engine_verdict`). Simulation only: real drones send neither."""

from __future__ import annotations

from collections.abc import Callable

from comms.keys import MissionKeys
from comms.latest_buffer import LatestValueBuffer
from comms.messages import CameraStats, PaceReport, decode


CLOCK_STALL_WALL_S = 60.0
"""Wall seconds without the mission clock moving, in flight, after which the run fails: the paced clock waits for
the cameras and the radio as long as they live, so a hung one must still end the run."""


class ClockStalled(RuntimeError):
    """The simulation clock stood still in flight for :data:`CLOCK_STALL_WALL_S`; the message says who it waits for."""


class PaceWatch:
    """Newest pace report and camera statistics; an agent newly left behind is an event."""

    def __init__(self, keys: MissionKeys, agent_timeout_s: float, events: Callable[[str], None]) -> None:
        self.keys = keys
        self.agent_timeout_s = agent_timeout_s
        self.events = events
        self.pace_report: PaceReport | None = None
        self.camera_stats: CameraStats | None = None
        self._left_behind_counts: dict[str, int] = {}
        self._clock_seen = (0.0, 0.0)

    def clock_moved(self, mission_t_s: float, now_wall_s: float) -> None:
        """The mission clock read ``mission_t_s`` at ``now_wall_s``."""
        self._clock_seen = (mission_t_s, now_wall_s)

    def check_clock_moves(self, mission_t_s: float, in_flight: bool, now_wall_s: float) -> None:
        """Raise :class:`ClockStalled` when the mission clock has stood still for :data:`CLOCK_STALL_WALL_S` in
        flight (on the ground a clock that waits is start-up, judged by its own timeout)."""
        if mission_t_s != self._clock_seen[0] or not in_flight:
            self.clock_moved(mission_t_s, now_wall_s)
        elif now_wall_s - self._clock_seen[1] > CLOCK_STALL_WALL_S:
            waiting = ", ".join(self.pace_report.waiting_for) if self.pace_report else "unknown"
            raise ClockStalled(f"the simulation clock has stood at {mission_t_s:.2f} s for {CLOCK_STALL_WALL_S:g} s "
                               f"of wall time (waiting for: {waiting})")

    def poll(self, buf: LatestValueBuffer) -> None:
        for item in buf.drain():
            if item.key == self.keys.pace_report:
                report = decode(PaceReport, item.payload)
                if report is not None:
                    self._take_report(report)
            else:
                stats = decode(CameraStats, item.payload)
                if stats is not None:
                    self.camera_stats = stats

    def _take_report(self, report: PaceReport) -> None:
        self.pace_report = report
        for p in report.participants:
            if p.times_left_behind > self._left_behind_counts.get(p.participant, 0):
                self.events(f"{'agent ' if p.participant.isdigit() else ''}{p.participant} left behind by the "
                            f"paced clock (silent for {self.agent_timeout_s:g} s of wall time)")
            self._left_behind_counts[p.participant] = p.times_left_behind
