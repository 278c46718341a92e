"""The simulator's health as the ground station hears it: the fleet's pace report (real-time factor, who the paced
clock left behind) and the cameras' frame statistics, the inputs of the engine verdict
(:func:`gcs.processes.run_verdict.engine_verdict`). Simulation only: real drones send neither."""

from __future__ import annotations

from collections.abc import Callable

from comms.keys import MissionKeys
from comms.latest_buffer import LatestValueBuffer
from comms.messages import CameraStats, PaceReport, decode


class PaceWatch:
    """Newest pace report and camera statistics; an agent newly left behind is an event."""

    def __init__(self, keys: MissionKeys, agent_timeout_s: float, events: Callable[[str], None]) -> None:
        self.keys = keys
        self.agent_timeout_s = agent_timeout_s
        self.events = events
        self.pace_report: PaceReport | None = None
        self.camera_stats: CameraStats | None = None
        self._left_behind_counts: dict[str, int] = {}

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
