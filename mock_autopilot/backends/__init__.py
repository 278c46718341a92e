"""Vehicle backends for the lockstep engine: one interface (:mod:`.interface`), two models of the same vehicle.

``KinematicBackend`` (:mod:`.kinematic`) is the paper's holonomic point with PX4 limits, vectorised over the fleet;
``Px4Backend`` (:mod:`.px4`) is the sans-IO mock PX4 driven through MAVLink, with commander modes and failsafes.
"""

from mock_autopilot.backends.interface import MAVSDK_MODE_NAMES, BackendState, VehicleBackend, VehicleRequest
from mock_autopilot.backends.kinematic import KinematicBackend
from mock_autopilot.backends.px4 import Px4Backend, px4_vehicle_configs

__all__ = [
    "MAVSDK_MODE_NAMES",
    "BackendState",
    "KinematicBackend",
    "Px4Backend",
    "VehicleBackend",
    "VehicleRequest",
    "px4_vehicle_configs",
]
