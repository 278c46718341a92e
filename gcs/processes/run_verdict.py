"""Two separate verdicts on a processes-engine run (pure): did the engine keep up, and was the flight safe?

A mission that "completes" on a machine that could not keep its agents at their control rate measures the machine,
not the method; a mission whose drones passed within a metre of each other was unsafe whether or not the engine kept
up. So the run gets two verdicts, never one:

* **engine health**: ``complete`` only when every agent held its control rate (acknowledged ticks per mission second
  within :data:`RATE_TOLERANCE` of nominal), none was left behind by the paced clock, and the cameras held their
  frame rate; otherwise ``degraded`` with the reasons;
* **safety**: failsafes the vehicles announced (PX4's "Failsafe" STATUSTEXT), pairs closer than 1 m and the closest
  approach (from the mission metrics). The paper mode's near misses are a safety result, not a degraded engine.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from enum import Enum
from typing import Any

from comms.messages import CameraStats, PaceReport
from mock_autopilot.pacing import tick_rate_hz

RATE_TOLERANCE = 0.95
"""An agent or camera holding at least this fraction of its nominal rate held it."""


class EngineHealth(Enum):
    COMPLETE = "complete"
    DEGRADED = "degraded"


@dataclass(frozen=True)
class EngineVerdict:
    """Engine health with its evidence: the clock, the achieved real-time factor, rates and who was left behind."""

    health: EngineHealth
    clock: str
    real_time_factor: float
    reasons: tuple[str, ...] = ()
    agent_rate_min_hz: float = math.nan
    agent_rate_nominal_hz: float = math.nan
    camera_rate_hz: float = math.nan
    camera_rate_nominal_hz: float = math.nan
    left_behind: tuple[str, ...] = ()
    slowest_wait_wall_s: float = math.nan
    held_wall_s: float = math.nan

    def as_json(self) -> dict[str, Any]:
        return {
            "health": self.health.value, "clock": self.clock,
            "real_time_factor": _finite_or_none(self.real_time_factor),
            "reasons": list(self.reasons), "agent_rate_min_hz": _finite_or_none(self.agent_rate_min_hz),
            "agent_rate_nominal_hz": _finite_or_none(self.agent_rate_nominal_hz),
            "camera_rate_hz": _finite_or_none(self.camera_rate_hz),
            "camera_rate_nominal_hz": _finite_or_none(self.camera_rate_nominal_hz),
            "left_behind": list(self.left_behind), "slowest_wait_wall_s": _finite_or_none(self.slowest_wait_wall_s),
            "held_wall_s": _finite_or_none(self.held_wall_s),
        }

    def text(self) -> str:
        """``engine complete (paced, 0.71x real time)`` or ``engine DEGRADED: reason; reason``."""
        factor = f"{self.real_time_factor:.2f}x real time" if math.isfinite(self.real_time_factor) else "factor unknown"
        if self.health is EngineHealth.COMPLETE:
            return f"engine complete ({self.clock} clock, {factor})"
        return f"engine DEGRADED ({self.clock} clock, {factor}): " + "; ".join(self.reasons)


@dataclass(frozen=True)
class SafetyVerdict:
    """Failsafes announced by the vehicles, pairs closer than 1 m and the closest approach [m]."""

    failsafes: tuple[str, ...] = field(default_factory=tuple)
    near_miss_pairs: int = 0
    closest_approach_m: float = math.nan

    def as_json(self) -> dict[str, Any]:
        return {"failsafes": list(self.failsafes), "failsafe_count": len(self.failsafes),
                "near_miss_pairs": self.near_miss_pairs, "closest_approach_m": _finite_or_none(self.closest_approach_m)}

    def text(self) -> str:
        closest = f"{self.closest_approach_m:.2f} m" if math.isfinite(self.closest_approach_m) else "unknown"
        return (f"safety: {len(self.failsafes)} failsafe{'s' if len(self.failsafes) != 1 else ''}, "
                f"{self.near_miss_pairs} pair{'s' if self.near_miss_pairs != 1 else ''} closer than 1 m, "
                f"closest approach {closest}")


def engine_verdict(report: PaceReport | None, cameras: CameraStats | None, agent_ids: Iterable[int],
                   control_rate_hz: float, clock: str, *, cameras_expected: bool = True,
                   tolerance: float = RATE_TOLERANCE) -> EngineVerdict:
    """Judge the engine from the simulator's last :class:`PaceReport` and the cameras' last :class:`CameraStats`."""
    if report is None:
        return EngineVerdict(EngineHealth.DEGRADED, clock, math.nan, ("no pace report from the simulator",))
    reasons: list[str] = []
    records = {p.participant: p for p in report.participants}
    rates: dict[int, float] = {}
    for vid in agent_ids:
        record = records.get(str(vid))
        if record is None:
            reasons.append(f"agent {vid} never reported a tick")
            continue
        rates[vid] = tick_rate_hz(record.ticks, record.first_t_s, record.last_t_s)
    slow = sorted(vid for vid, hz in rates.items() if not hz >= tolerance * control_rate_hz)
    if slow:
        worst = min((rates[v] for v in slow if math.isfinite(rates[v])), default=math.nan)
        reasons.append(f"{len(slow)} agent{'s' if len(slow) != 1 else ''} below {tolerance:.0%} of the "
                       f"{control_rate_hz:g} Hz control rate (slowest {worst:.1f} Hz): {_ids(slow)}")
    left = tuple(p.participant for p in report.participants if p.times_left_behind > 0)
    if left:
        reasons.append(f"left behind by the paced clock: {', '.join(left)}")
    camera_hz = cameras.frame_rate_hz if cameras is not None else math.nan
    camera_nominal_hz = cameras.nominal_rate_hz if cameras is not None else math.nan
    if cameras_expected:
        if cameras is None:
            reasons.append("no camera statistics")
        elif not camera_hz >= tolerance * camera_nominal_hz:
            reasons.append(f"cameras at {camera_hz:.2f} Hz of {camera_nominal_hz:g} Hz per airborne vehicle")
    finite_rates = [hz for hz in rates.values() if math.isfinite(hz)]
    waits = [p.max_wait_wall_s for p in report.participants]
    return EngineVerdict(
        health=EngineHealth.DEGRADED if reasons else EngineHealth.COMPLETE,
        clock=clock,
        real_time_factor=report.real_time_factor,
        reasons=tuple(reasons),
        agent_rate_min_hz=min(finite_rates, default=math.nan),
        agent_rate_nominal_hz=control_rate_hz,
        camera_rate_hz=camera_hz,
        camera_rate_nominal_hz=camera_nominal_hz,
        left_behind=left,
        slowest_wait_wall_s=max(waits, default=math.nan),
        held_wall_s=report.held_wall_s,
    )


def safety_verdict(summary: Mapping[str, Any], failsafes: Iterable[str]) -> SafetyVerdict:
    """Safety from the mission metrics' summary (``near_miss_pairs``, ``min_pairwise_distance_m``) and the
    failsafes the vehicles announced."""
    pairs = summary.get("near_miss_pairs")
    closest = summary.get("min_pairwise_distance_m")
    return SafetyVerdict(
        failsafes=tuple(failsafes),
        near_miss_pairs=int(pairs) if isinstance(pairs, (int, float)) and math.isfinite(pairs) else 0,
        closest_approach_m=float(closest) if isinstance(closest, (int, float)) else math.nan,
    )


def _ids(ids: list[int]) -> str:
    shown = ", ".join(str(v) for v in ids[:8])
    return shown + (f" and {len(ids) - 8} more" if len(ids) > 8 else "")


def _finite_or_none(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None
