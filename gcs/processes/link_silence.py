"""When the ground station calls a vehicle lost, and when it may not judge at all (pure; times passed in).

A vehicle is lost when no heartbeat reached the GCS link for ``lost_after_s`` of wall time. That judgement needs the
ground station itself to have been listening: on a starved host its own loop may not run for a second or more, and
meanwhile every vehicle's heartbeats wait unread in the socket. When the loop comes back, the first pass finds all of
them old and would call the whole fleet lost although nothing was silent. So a pass that follows a gap longer than
``own_stall_s`` opens a grace of ``own_stall_s``, during which the loop reads the backlog and no new loss is declared;
a vehicle that is really silent is reported that much later.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

OWN_STALL_S = 0.5
"""A gap [wall s] between two passes of the ground station's loop beyond which it counts as having stalled."""


@dataclass(frozen=True)
class SilenceVerdict:
    """What one pass found: vehicles newly lost, vehicles heard again, the ground station's own stall [s] (0: none),
    and the vehicles that looked silent only because it had stalled (not called lost)."""

    lost: tuple[int, ...]
    back: tuple[int, ...]
    own_stall_s: float
    spared: tuple[int, ...] = ()


@dataclass
class SilenceJudge:
    """Heartbeat silence per vehicle, judged only while the ground station has been listening."""

    lost_after_s: float
    own_stall_s: float = OWN_STALL_S
    silent: set[int] = field(default_factory=set)
    _last_pass_s: float = math.nan
    _judge_after_s: float = -math.inf

    def step(self, now_s: float, heartbeat_ages_s: Mapping[int, float], judging: bool = True) -> SilenceVerdict:
        """One pass of the loop at wall time ``now_s`` with each vehicle's heartbeat age [s] (inf: never heard);
        ``judging`` False (before take-off) only keeps track of the loop's own gaps."""
        gap_s = now_s - self._last_pass_s if math.isfinite(self._last_pass_s) else 0.0
        self._last_pass_s = now_s
        stall_s = gap_s if gap_s > self.own_stall_s else 0.0
        if stall_s:
            self._judge_after_s = now_s + self.own_stall_s
        if not judging:
            return SilenceVerdict((), (), stall_s)
        may_lose = now_s >= self._judge_after_s
        lost, back, spared = [], [], []
        for vid, age_s in heartbeat_ages_s.items():
            quiet = age_s > self.lost_after_s
            if quiet and vid not in self.silent:
                if may_lose:
                    self.silent.add(vid)
                    lost.append(vid)
                elif stall_s:
                    spared.append(vid)
            elif not quiet and vid in self.silent:
                self.silent.discard(vid)
                back.append(vid)
        return SilenceVerdict(tuple(lost), tuple(back), stall_s, tuple(spared))
