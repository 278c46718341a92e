"""Fault injection as data: what can go wrong with a vehicle, when, and the CLI spelling of it.

CLI form: ``KIND:INSTANCE[:VALUE]@T_S`` (T_S in simulated seconds after the fleet starts), e.g.
``kill:3@40``, ``gps:1@20`` (lose GPS), ``battery:2:0.1@30`` (drain to 10 %), ``drop:0@10`` (drop every
datagram of both links), ``delay:0:0.5@10`` (delay both links by 0.5 simulated seconds), ``restore:0@20``
(end drop and delay). PX4 offers the same through its ``failure`` shell command for SITL.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

FAULT_KINDS = ("kill", "gps", "battery", "drop", "delay", "restore")
_NEEDS_VALUE = ("battery", "delay")


class FaultSpecError(ValueError):
    """A fault specification that cannot be understood; the message says why in one line."""


@dataclass(frozen=True)
class FaultSpec:
    """One scheduled fault: ``kind`` on vehicle ``instance`` (0-based) at simulated ``at_s``."""

    kind: str
    instance: int
    at_s: float
    value: float = math.nan


def parse_fault(text: str) -> FaultSpec:
    """Parse ``KIND:INSTANCE[:VALUE]@T_S``."""
    body, sep, when = text.partition("@")
    parts = body.split(":")
    if not sep or len(parts) not in (2, 3):
        raise FaultSpecError(f"fault {text!r}: expected KIND:INSTANCE[:VALUE]@T_S")
    kind = parts[0]
    if kind not in FAULT_KINDS:
        raise FaultSpecError(f"fault {text!r}: kind must be one of {', '.join(FAULT_KINDS)}")
    try:
        instance = int(parts[1])
        at_s = float(when)
        value = float(parts[2]) if len(parts) == 3 else math.nan
    except ValueError as exc:
        raise FaultSpecError(f"fault {text!r}: {exc}") from exc
    if instance < 0 or not math.isfinite(at_s) or at_s < 0:
        raise FaultSpecError(f"fault {text!r}: instance and time must be >= 0")
    if kind in _NEEDS_VALUE and not (math.isfinite(value) and value >= 0):
        raise FaultSpecError(f"fault {text!r}: {kind} needs a VALUE >= 0")
    return FaultSpec(kind, instance, at_s, value)
