"""The mission CLI's parsed flags as one frozen value, handed to whichever engine runs the mission."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from mission_plan.control_params import ControlMode

ENGINES = ("processes", "lockstep")
CLOCKS = ("paced", "free")
"""The processes engine's simulation clock: ``paced`` waits at each control tick for every live agent, the
cameras and the radio (``mock_autopilot.pacing``); ``free`` runs at ``--speed`` whatever they do (for testing
real-time faults)."""
BACKENDS = ("kinematic", "px4")
"""Vehicle dynamics of a lockstep run (``gcs.lockstep.backend_choice.BackendKind``); the processes engine always
flies the mock PX4 fleet."""


@dataclass(frozen=True)
class MissionOptions:
    """Flags of ``python -m gcs.mission``.

    ``seed`` and ``duration_s`` are already applied to the scenario the engine receives; they are kept here for
    the record. ``speed`` is the simulation speed-up of the process engine (the lockstep engine runs as fast as it
    can). ``out_dir`` is where every output goes (created by the engine).
    """

    scenario: str
    engine: str = "processes"
    mode: str = ControlMode.IMPROVED
    seed: int | None = None
    duration_s: float | None = None
    speed: float = 1.0
    out_dir: Path = Path("runs")
    overrides: tuple[str, ...] = ()
    base_port: int = 14540
    gcs_port: int = 14550
    live: bool = True
    backend: str = "kinematic"
    """Lockstep only: ``kinematic`` (default) or ``px4`` (the mock PX4's mode logic and failsafes in the loop)."""
    clock: str = "paced"
    agent_timeout_s: float = 2.0
    """Paced clock: wall seconds an agent may hold a tick before the clock goes on without it."""
    startup_timeout_s: float = 60.0
    """Processes engine: wall seconds start-up may go without one more agent connecting before the run fails."""
    strict: bool = False
    """Exit non-zero when the engine was degraded (an agent or the cameras did not keep their rate)."""
    key_file: Path | None = None
    """The mission key to sign with (``comms.key_file``); None: a new one per mission."""
    dashboard_port: int | None = 8080
    """Processes engine: the live map's port (busy: a free one, printed; 0: any free one); None: no live map."""
    dashboard_host: str = "127.0.0.1"
    dashboard_token: str | None = None
    dashboard_tiles: Path | None = None
    start_agents: bool = True
    """Processes engine: False (``--no-agents``) starts no agent; they run on the drones' companion computers
    (other hosts) and join over Zenoh, as in the field."""
    fleet_bind: str | None = None
    """Processes engine: the address the mock fleet's MAVLink sockets bind (``--fleet-bind``; default loopback)."""
    onboard_partners: tuple[str, ...] = ()
    """Processes engine: ``IDS=IP`` items, where those vehicles' onboard links send (their companion computers)."""
