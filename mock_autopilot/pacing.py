"""Who a paced simulation clock waits for, and when it moves on: the pure state machine behind ``--clock paced``.

One control tick of a paced run (mission time ``t`` = k x period, the clock held at ``t`` throughout):

1. ``ADVANCING``: the fleet's clock runs up to its gate ``t``; once it stands there the fleet publishes its truth
   for ``t`` (:attr:`PaceAction.PUBLISH_TRUTH`);
2. ``SERVICES``: the camera process renders the frames due by ``t`` and the radio delivers the messages due by ``t``;
   each acknowledges ``t`` (a :class:`~comms.messages.PaceAck`). Then the clock tick for ``t`` goes out
   (:attr:`PaceAction.PUBLISH_CLOCK`);
3. ``AGENTS``: every agent computes its tick for ``t`` on the newest telemetry, frame and inbox, sends its setpoint
   and state message and acknowledges ``t``. Then the gate moves to ``t`` + period (:attr:`PaceAction.SET_GATE`).

A participant is waited for from its first acknowledgement until it says it is leaving or its process is gone
(its liveliness token vanished). An agent that keeps the clock waiting longer than ``agent_timeout_s`` of wall time
is left behind: the clock goes on without it (its vehicle then meets PX4's offboard-loss rule in mission time) until
it acknowledges a current tick again. The cameras and the radio are part of the simulator, like a simulator's
sensors: they are waited for as long as their process lives, however slow (a first frame that takes seconds to
render delays the run; it must not change it). Everything here takes
wall times as arguments; the fleet process (:mod:`mock_autopilot.sim_bridge`) is the shell that reads clocks and
sockets.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

SERVICES: frozenset[str] = frozenset({"cameras", "radio"})
"""Participants that act in the SERVICES stage; every other name is an agent (its vehicle id)."""
CLOCK_REPEAT_WALL_S = 0.5
"""While agents are awaited, the clock tick is published again this often (a participant that joined late hears it)."""


class PaceStage(Enum):
    ADVANCING = "advancing"
    SERVICES = "services"
    AGENTS = "agents"


class PaceActionKind(Enum):
    PUBLISH_TRUTH = "publish_truth"
    PUBLISH_CLOCK = "publish_clock"
    SET_GATE = "set_gate"
    LEFT_BEHIND = "left_behind"
    REJOINED = "rejoined"


@dataclass(frozen=True)
class PaceAction:
    """What the shell must do: publish truth or the clock tick for ``t_s``, move the gate to ``t_s``, or log that
    ``participant`` was left behind / rejoined."""

    kind: PaceActionKind
    t_s: float
    participant: str = ""


def tick_rate_hz(ticks: int, first_t_s: float, last_t_s: float) -> float:
    """Achieved rate of ``ticks`` acknowledged between mission times ``first_t_s`` and ``last_t_s`` (NaN before two)."""
    span_s = last_t_s - first_t_s
    return (ticks - 1) / span_s if ticks > 1 and span_s > 0 else math.nan


@dataclass
class ParticipantRecord:
    """One participant as the pacer sees it (mission times of its acknowledgements, wall time of its waits)."""

    first_t_s: float
    last_t_s: float
    ticks: int = 1
    max_wait_wall_s: float = 0.0
    left_behind: bool = False
    times_left_behind: int = 0
    leaving: bool = False

    def rate_hz(self) -> float:
        """Ticks per mission second over the span it acknowledged (NaN before two ticks)."""
        return tick_rate_hz(self.ticks, self.first_t_s, self.last_t_s)


class Pacer:
    """The paced clock's bookkeeping: acknowledgements in, :class:`PaceAction` lists out (no I/O, no clock).

    With ``paced`` False it only keeps the records (ticks, rates) of a free-running clock's participants.
    """

    def __init__(self, period_s: float, agent_timeout_s: float, *, paced: bool = True, first_tick: int = 1) -> None:
        if not period_s > 0:
            raise ValueError(f"period_s must be > 0, got {period_s}")
        if not agent_timeout_s > 0:
            raise ValueError(f"agent timeout must be > 0 s, got {agent_timeout_s}")
        self.period_s = period_s
        self.agent_timeout_s = agent_timeout_s
        self.paced = paced
        self.tick = first_tick
        self.stage = PaceStage.ADVANCING
        self.records: dict[str, ParticipantRecord] = {}
        self._wait_started_wall_s = 0.0
        self._clock_sent_wall_s = -math.inf

    @property
    def gate_s(self) -> float:
        """The mission time the clock may run up to: the current tick (k x period, no summed rounding)."""
        return self.tick * self.period_s

    def on_ack(self, participant: str, t_s: float, leaving: bool, wall_s: float) -> list[PaceAction]:
        """Record one acknowledgement; returns a REJOINED action when a left-behind participant caught up."""
        record = self.records.get(participant)
        if record is None:
            self.records[participant] = ParticipantRecord(first_t_s=t_s, last_t_s=t_s, leaving=leaving)
            return []
        actions: list[PaceAction] = []
        if t_s > record.last_t_s:
            record.ticks += 1
            record.last_t_s = t_s
            if self.paced and self._awaited_stage(participant) is self.stage and t_s >= self.gate_s - 1e-9:
                record.max_wait_wall_s = max(record.max_wait_wall_s, wall_s - self._wait_started_wall_s)
        record.leaving = record.leaving or leaving
        if record.left_behind and t_s >= self.gate_s - self.period_s - 1e-9:
            record.left_behind = False
            actions.append(PaceAction(PaceActionKind.REJOINED, t_s, participant))
        return actions

    def on_departed(self, participant: str) -> None:
        """The participant's process is gone (its liveliness token vanished): stop waiting for it at once."""
        record = self.records.get(participant)
        if record is not None:
            record.leaving = True

    def step(self, clock_held: bool, wall_s: float) -> list[PaceAction]:
        """Advance the stage machine as far as the acknowledgements allow at wall time ``wall_s``, at most to the
        next gate (``clock_held``: the fleet has reached the current gate, physics and telemetry included)."""
        if not self.paced:
            return []
        actions: list[PaceAction] = []
        while True:
            if self.stage is PaceStage.ADVANCING:
                if not clock_held:
                    return actions
                actions.append(PaceAction(PaceActionKind.PUBLISH_TRUTH, self.gate_s))
                self._enter(PaceStage.SERVICES, wall_s)
            elif self.stage is PaceStage.SERVICES:
                if self._still_waiting(PaceStage.SERVICES, wall_s, actions):
                    return actions
                actions.append(PaceAction(PaceActionKind.PUBLISH_CLOCK, self.gate_s))
                self._clock_sent_wall_s = wall_s
                self._enter(PaceStage.AGENTS, wall_s)
            else:
                if self._still_waiting(PaceStage.AGENTS, wall_s, actions):
                    if wall_s - self._clock_sent_wall_s >= CLOCK_REPEAT_WALL_S:
                        actions.append(PaceAction(PaceActionKind.PUBLISH_CLOCK, self.gate_s))
                        self._clock_sent_wall_s = wall_s
                    return actions
                self.tick += 1
                actions.append(PaceAction(PaceActionKind.SET_GATE, self.gate_s))
                self._enter(PaceStage.ADVANCING, wall_s)
                return actions  # ``clock_held`` was about the old gate

    def waiting_for(self) -> list[str]:
        """Participants the current stage still waits for."""
        if self.stage is PaceStage.ADVANCING:
            return []
        return [name for name, record in self.records.items()
                if self._awaited_stage(name) is self.stage and self._awaited(record)]

    def _enter(self, stage: PaceStage, wall_s: float) -> None:
        self.stage = stage
        self._wait_started_wall_s = wall_s

    def _awaited(self, record: ParticipantRecord) -> bool:
        return not record.leaving and not record.left_behind and record.last_t_s < self.gate_s - 1e-9

    @staticmethod
    def _awaited_stage(participant: str) -> PaceStage:
        return PaceStage.SERVICES if participant in SERVICES else PaceStage.AGENTS

    def _still_waiting(self, stage: PaceStage, wall_s: float, actions: list[PaceAction]) -> bool:
        """Leave behind agents that have kept this stage waiting too long; True while anyone is still awaited."""
        waiting = False
        for name, record in self.records.items():
            if self._awaited_stage(name) is not stage or not self._awaited(record):
                continue
            if stage is PaceStage.AGENTS and wall_s - self._wait_started_wall_s > self.agent_timeout_s:
                record.left_behind = True
                record.times_left_behind += 1
                record.max_wait_wall_s = max(record.max_wait_wall_s, wall_s - self._wait_started_wall_s)
                actions.append(PaceAction(PaceActionKind.LEFT_BEHIND, self.gate_s, name))
            else:
                waiting = True
        return waiting
