"""The paced simulation clock's messages: the clock's tick, each participant's acknowledgement, the clock's own
report, and the cameras' frame statistics (Zenoh keys ``sim/...``; simulation only)."""

from __future__ import annotations

import math

import msgspec

from comms.message_checks import InvalidMessage


class SimClockTick(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/clock/1"):
    """The simulation clock has reached ``t_s`` (mission seconds) and every input for that instant is out.

    A paced simulation (``--clock paced``) publishes one per control period once the fleet is held at ``t_s`` and
    the camera and radio processes have delivered what is due by then; agents compute their tick for ``t_s`` on it,
    as a PX4 SITL companion does on Gazebo's clock. ``paced`` False: a free-running clock, for information.
    """

    t_s: float
    seq: int
    paced: bool = True

    def __post_init__(self) -> None:
        if not math.isfinite(self.t_s):
            raise InvalidMessage("non-finite t_s")


class PaceAck(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/pace/1"):
    """A participant of the simulation has done everything it owes for mission time ``t_s``.

    ``participant``: a vehicle id as text (its agent sent its setpoint and state message for that tick), or
    ``cameras`` / ``radio`` (frames due by ``t_s`` rendered and published; messages due by ``t_s`` delivered).
    ``leaving``: the participant is exiting on purpose and must no longer be waited for.
    """

    participant: str
    t_s: float
    leaving: bool = False

    def __post_init__(self) -> None:
        if not math.isfinite(self.t_s):
            raise InvalidMessage("non-finite t_s")


class ParticipantPace(msgspec.Struct, frozen=True, omit_defaults=True):
    """One participant's record in a :class:`PaceReport`: ticks done between the mission times ``first_t_s`` and
    ``last_t_s`` (its achieved rate), the slowest wait it caused, whether it is left behind (silent for longer than
    the agent timeout) and how often that happened."""

    participant: str
    ticks: int
    first_t_s: float
    last_t_s: float
    max_wait_wall_s: float
    left_behind: bool = False
    times_left_behind: int = 0
    leaving: bool = False


class PaceReport(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/pacereport/1"):
    """The simulation clock's own account, published by the fleet once per wall second and at the end.

    ``real_time_factor``: mission seconds per wall second since the clock started (over the last report period in
    ``recent_real_time_factor``); ``held_wall_s``: wall time the clock stood still waiting for participants.
    """

    t_s: float
    wall_s: float
    paced: bool
    real_time_factor: float
    recent_real_time_factor: float
    held_wall_s: float
    participants: list[ParticipantPace] = []
    waiting_for: list[str] = []
    """Who the clock is waiting for right now (a paced clock that stands still says why)."""


class CameraStats(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/camerastats/1"):
    """The camera process's achieved frame rate per airborne camera vehicle [Hz of mission time] and its nominal."""

    t_s: float
    frames_sent: int
    frame_rate_hz: float
    nominal_rate_hz: float
