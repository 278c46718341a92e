"""The fleet process's side of the paced clock: acknowledgements in from Zenoh, truth, clock ticks and the gate out.

:class:`PaceKeeper` runs the pure :class:`mock_autopilot.pacing.Pacer` against the fleet's clock and the mission's
Zenoh session. With a free clock it still listens: the acknowledgements then only measure each participant's
achieved rate, and the :class:`~comms.messages.PaceReport` says so (``paced`` False).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable

from comms.keys import MissionKeys
from comms.messages import PaceAck, PaceReport, ParticipantPace, SimClockTick, decode, encode
from comms.zenoh_session import ZenohSession
from mock_autopilot.pacing import PaceAction, PaceActionKind, Pacer

log = logging.getLogger("mock_autopilot.sim_bridge")

REPORT_PERIOD_WALL_S = 1.0


class PaceKeeper:
    """Drives the gate of ``set_gate`` from the acknowledgements; ``publish_truth(t_s)`` sends the fleet's truth."""

    def __init__(self, session: ZenohSession, mission: str, pacer: Pacer, now_s: Callable[[], float],
                 reached_s: Callable[[], float], set_gate: Callable[[float], None],
                 publish_truth: Callable[[float], None]) -> None:
        self.session = session
        self.keys = MissionKeys(mission)
        self.pacer = pacer
        self._now_s = now_s
        self._reached_s = reached_s
        self._set_gate = set_gate
        self._publish_truth = publish_truth
        self._acks = session.subscribe(self.keys.all_pace)
        self._alive = session.subscribe_alive(self.keys.all_alive, history=False)
        self._clock_seq = 0
        self._wall_start_s = time.monotonic()
        self._t_start_s = now_s()
        self._next_report_wall_s = self._wall_start_s + REPORT_PERIOD_WALL_S
        self._last_report: tuple[float, float] = (self._wall_start_s, self._t_start_s)
        self._reached_wall_s: float | None = None
        self.held_wall_s = 0.0
        """Wall seconds the clock stood at a gate it had reached, waiting for participants."""
        self.rejected_acks = 0

    def wait(self, timeout_s: float) -> None:
        """Sleep until an acknowledgement arrives or ``timeout_s`` passes."""
        self._acks.wait(timeout_s)

    def poll(self) -> None:
        """Take the acknowledgements that arrived, advance the pacer, do what it says, report once a second."""
        wall_s = time.monotonic()
        actions: list[PaceAction] = []
        for item in self._acks.drain():
            ack = decode(PaceAck, item.payload)
            if ack is None or item.key != self.keys.pace(ack.participant):
                self.rejected_acks += 1
                continue
            actions += self.pacer.on_ack(ack.participant, ack.t_s, ack.leaving, wall_s)
        for item in self._alive.drain():
            name = self.keys.participant_of(item.key)
            if item.kind == "delete" and name is not None:
                self.pacer.on_departed(name)
        held = self._reached_s() >= self.pacer.gate_s - 1e-9
        if held and self._reached_wall_s is None:
            self._reached_wall_s = wall_s
        actions += self.pacer.step(held, wall_s)
        for action in actions:
            self._do(action, wall_s)
        if wall_s >= self._next_report_wall_s:
            self.report(wall_s)
            self._next_report_wall_s = wall_s + REPORT_PERIOD_WALL_S

    def _do(self, action: PaceAction, wall_s: float) -> None:
        if action.kind is PaceActionKind.PUBLISH_TRUTH:
            self._publish_truth(action.t_s)
        elif action.kind is PaceActionKind.PUBLISH_CLOCK:
            self._clock_seq += 1
            self.session.put(self.keys.clock, encode(SimClockTick(t_s=action.t_s, seq=self._clock_seq)))
        elif action.kind is PaceActionKind.SET_GATE:
            if self._reached_wall_s is not None:
                self.held_wall_s += wall_s - self._reached_wall_s
                self._reached_wall_s = None
            self._set_gate(action.t_s)
        elif action.kind is PaceActionKind.LEFT_BEHIND:
            log.warning("pace: %s silent for %.1f s of wall time at mission time %.2f s: left behind",
                        action.participant, self.pacer.agent_timeout_s, action.t_s)
        elif action.kind is PaceActionKind.REJOINED:
            log.info("pace: %s back at mission time %.2f s", action.participant, action.t_s)

    def next_wait_s(self) -> float:
        """How long the shell may sleep: until the gate is reached when the clock runs, briefly otherwise."""
        ahead_s = self.pacer.gate_s - self._now_s()
        return 0.02 if ahead_s <= 0 else min(0.05, ahead_s)

    def report(self, wall_s: float | None = None) -> PaceReport:
        """Publish (and return) the clock's account so far."""
        wall_s = time.monotonic() if wall_s is None else wall_s
        t_s = self._now_s()
        elapsed_s = wall_s - self._wall_start_s
        last_wall_s, last_t_s = self._last_report
        recent_s = wall_s - last_wall_s
        self._last_report = (wall_s, t_s)
        report = PaceReport(
            t_s=t_s, wall_s=elapsed_s, paced=self.pacer.paced,
            real_time_factor=(t_s - self._t_start_s) / elapsed_s if elapsed_s > 0 else math.nan,
            recent_real_time_factor=(t_s - last_t_s) / recent_s if recent_s > 0 else math.nan,
            held_wall_s=self.held_wall_s,
            participants=[
                ParticipantPace(participant=name, ticks=r.ticks, first_t_s=r.first_t_s, last_t_s=r.last_t_s,
                                max_wait_wall_s=r.max_wait_wall_s, left_behind=r.left_behind,
                                times_left_behind=r.times_left_behind, leaving=r.leaving)
                for name, r in sorted(self.pacer.records.items())
            ],
            waiting_for=sorted(self.pacer.waiting_for()),
        )
        self.session.put(self.keys.pace_report, encode(report))
        return report
