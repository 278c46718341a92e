"""Fault injection as data: what can go wrong with a vehicle, when, and the CLI spelling of it.

CLI form: ``KIND:INSTANCE[:VALUE]@T_S`` (T_S in simulated seconds after the fleet starts), e.g.
``kill:3@40``, ``gps:1@20`` (lose GPS), ``battery:2:0.1@30`` (drain to 10 %), ``drop:0@10`` (drop every
datagram of both links), ``delay:0:0.5@10`` (delay both links by 0.5 simulated seconds), ``restore:0@20``
(end drop and delay). PX4 offers the same through its ``failure`` shell command for SITL.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Protocol, Sequence

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
    if kind not in FAULT_EFFECTS:
        raise FaultSpecError(f"fault {text!r}: kind must be one of {', '.join(FAULT_EFFECTS)}")
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


class FaultableVehicle(Protocol):
    """What a fault does to a vehicle (:class:`mock_autopilot.vehicle.Vehicle` has it)."""

    def kill(self) -> None: ...
    def set_gps_available(self, available: bool, now_s: float) -> None: ...
    def set_battery_remaining(self, fraction: float) -> None: ...


class FaultableLink(Protocol):
    """What a fault does to a link (:class:`mock_autopilot.udp_link.UdpLink` has it)."""

    dropped_by_fault: bool
    delay_s: float


def _kill(vehicle: FaultableVehicle, links: Sequence[FaultableLink], fault: FaultSpec, now_s: float) -> None:
    vehicle.kill()


def _lose_gps(vehicle: FaultableVehicle, links: Sequence[FaultableLink], fault: FaultSpec, now_s: float) -> None:
    vehicle.set_gps_available(False, now_s)


def _drain_battery(vehicle: FaultableVehicle, links: Sequence[FaultableLink], fault: FaultSpec, now_s: float) -> None:
    vehicle.set_battery_remaining(fault.value)


def _drop(vehicle: FaultableVehicle, links: Sequence[FaultableLink], fault: FaultSpec, now_s: float) -> None:
    for link in links:
        link.dropped_by_fault = True


def _delay(vehicle: FaultableVehicle, links: Sequence[FaultableLink], fault: FaultSpec, now_s: float) -> None:
    for link in links:
        link.delay_s = fault.value


def _restore(vehicle: FaultableVehicle, links: Sequence[FaultableLink], fault: FaultSpec, now_s: float) -> None:
    for link in links:
        link.dropped_by_fault = False
        link.delay_s = 0.0


FaultEffect = Callable[[FaultableVehicle, Sequence[FaultableLink], FaultSpec, float], None]

FAULT_EFFECTS: dict[str, FaultEffect] = {
    "kill": _kill,
    "gps": _lose_gps,
    "battery": _drain_battery,
    "drop": _drop,
    "delay": _delay,
    "restore": _restore,
}
"""Fault kind -> what it does to the vehicle and its links at simulated time ``now_s``."""
