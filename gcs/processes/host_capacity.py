"""Will this machine keep up? A pure estimate of the CPU a processes-engine mission needs (warned about, not enforced).

An overloaded simulation host is not a safe one: agents fall behind their control rate, setpoints reach the
autopilots late, PX4's offboard-loss failsafe fires and drones pass closer than the collision barrier allows
(docs/BENCHMARKS.md, Mission). The figures below are the per-process CPU shares measured there on a 2-core Xeon:
an agent costs ~4.5 % of a core at 5 Hz, ~6.5 % at 10 Hz and ~10 % at 20 Hz of wall-clock control rate (a fixed part
for MAVSDK's and Zenoh's threads plus a part per step, which grows with the neighbours it hears), and the fleet,
camera, radio and ground-station processes together ~0.55 core for 13 vehicles, growing slowly with the fleet.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

NICE_WEIGHTS = (1024, 820, 655, 526, 423, 335, 272, 215, 172, 137, 110, 87, 70, 56, 45, 36, 29, 23, 18, 15)
"""The Linux scheduler's weight of nice 0..19 (``sched_prio_to_weight``): a nice-0 process weighs 1024."""
AGENTS_SHARE = 4.0
"""How many nice-0 processes' worth of CPU the whole fleet of agents weighs against the simulator's processes."""
AGENT_MIN_NICENESS = 5
"""Even a small fleet's agents run below the simulator, which must keep its clock (a paced one waits anyway)."""

AGENT_FIXED_CORES = 0.027
"""An idle agent's share of a core (MAVSDK's and Zenoh's own threads, telemetry)."""
AGENT_CORES_PER_HZ = 0.0036
"""An agent's extra share of a core per control step per wall second, hearing 12 neighbours (``circle``)."""
AGENT_CORES_PER_HZ_PER_NEIGHBOUR = 0.000077
"""... and per neighbour heard beyond (or short of) those 12: the main thread decodes, checks and files every state
it hears each tick. Measured on `large` as processes (every agent hears ~207 at its 100 m radio range): 17.8 ms per
tick against 2.7 ms hearing 12, i.e. (17.8 - 2.7) ms / 195 neighbours (docs/BENCHMARKS.md)."""
NEIGHBOURS_MEASURED = 12
"""The neighbours an agent of ``circle`` hears: what :data:`AGENT_CORES_PER_HZ` was measured with."""
SERVICES_CORES = 0.45
"""Fleet, cameras, radio and ground station, without vehicles (measured nearly flat from x1 to x2)."""
SERVICES_CORES_PER_VEHICLE = 0.008
WARN_ABOVE = 1.1
"""Warn when the estimate exceeds this many times the machine's cores. The shares were measured on a busy machine,
where every process got a little less than it asked, so the estimate runs high: on 2 cores the runs that held
estimate up to 2.1 cores (13 agents at 20 Hz x1.25, 19 at 10 Hz, 25 at 5 Hz), those that did not 2.25 and more
(34 at 5 Hz held once and failed once, 19 at 20 Hz, 13 at 20 Hz x1.5)."""


@dataclass(frozen=True)
class CapacityEstimate:
    """Cores the mission is expected to need against the cores this machine has."""

    needed_cores: float
    available_cores: int

    @property
    def fits(self) -> bool:
        return self.needed_cores <= WARN_ABOVE * self.available_cores

    def warning(self, vehicles: int, control_rate_hz: float, speed: float, paced: bool = False) -> str | None:
        """One line for the user when the mission is not expected to keep up, else None.

        With a paced clock nothing breaks, the run only slows down: the line says by about how much.
        """
        if self.fits:
            return None
        if paced:
            factor = speed * WARN_ABOVE * self.available_cores / self.needed_cores
            return (f"note: {vehicles} agents at {control_rate_hz:g} Hz x{speed:g} need about {self.needed_cores:.1f} "
                    f"cores, this machine has {self.available_cores}: the paced clock will hold them, expect about "
                    f"{factor:.1g}x real time")
        return (f"warning: {vehicles} agents at {control_rate_hz:g} Hz x{speed:g} need about {self.needed_cores:.1f} "
                f"cores, this machine has {self.available_cores}: agents will fall behind and vehicles may pass too "
                "close; lower --speed or control_rate_hz, or use --engine lockstep")


def agent_niceness(fleet_size: int) -> int:
    """The nice value (0..19) of each agent's autogroup whose weight comes nearest to the agents together weighing
    :data:`AGENTS_SHARE` nice-0 processes, whatever their number.

    Each agent runs in its own session, which Linux schedules as an autogroup of its own: 13 agents at nice 5
    weigh 4.3 simulator processes, but 208 at nice 5 would weigh 68 and leave the simulator 1 % of a busy machine.
    """
    per_agent = AGENTS_SHARE * NICE_WEIGHTS[0] / max(1, fleet_size)
    nearest = min(range(len(NICE_WEIGHTS)), key=lambda nice: abs(NICE_WEIGHTS[nice] - per_agent))
    return max(AGENT_MIN_NICENESS, nearest)


def estimate_capacity(vehicles: int, control_rate_hz: float, speed: float, available_cores: int) -> CapacityEstimate:
    """The estimate for ``vehicles`` agents stepping at ``control_rate_hz`` of mission time, ``speed`` times faster
    than the wall clock, on ``available_cores``; every agent is taken to hear all the others (an upper bound, and
    what the agents of ``circle`` and ``large`` do)."""
    wall_rate_hz = control_rate_hz * speed
    heard_beyond = max(vehicles - 1, 0) - NEIGHBOURS_MEASURED
    per_step = AGENT_CORES_PER_HZ + AGENT_CORES_PER_HZ_PER_NEIGHBOUR * heard_beyond
    agents = vehicles * (AGENT_FIXED_CORES + per_step * wall_rate_hz)
    services = SERVICES_CORES + SERVICES_CORES_PER_VEHICLE * vehicles
    return CapacityEstimate(needed_cores=agents + services, available_cores=max(1, available_cores))


def host_warning(vehicles: int, control_rate_hz: float, speed: float, paced: bool) -> str | None:
    """The one line to show when this machine (the cores this process may use) is not expected to keep up."""
    estimate = estimate_capacity(vehicles, control_rate_hz, speed, len(os.sched_getaffinity(0)))
    return estimate.warning(vehicles, control_rate_hz, speed, paced=paced)
