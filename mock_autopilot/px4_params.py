"""PX4 parameters as data: names, PX4 types, defaults and ranges, plus the MAVLink wire encoding.

PX4 sends INT32 parameters "bytewise": the four bytes of the int32 travel in PARAM_VALUE.param_value's float
slot (MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_BYTEWISE). REAL32 parameters travel as floats. Every parameter here
changes the mock's behaviour (see :mod:`mock_autopilot.vehicle`); values outside [min, max] or not finite are
refused and the current value is sent back, as a PX4 client expects a PARAM_VALUE in answer to every PARAM_SET.
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass
from enum import IntEnum
from typing import Mapping


class ParamType(IntEnum):
    """MAV_PARAM_TYPE values PX4 uses."""

    INT32 = 6
    REAL32 = 9


@dataclass(frozen=True)
class ParamSpec:
    """One PX4 parameter: type, default and accepted range (inclusive)."""

    name: str
    type: ParamType
    default: float
    min_value: float
    max_value: float


_I = ParamType.INT32
_F = ParamType.REAL32

PARAM_TABLE: tuple[ParamSpec, ...] = (
    ParamSpec("BAT_CRIT_THR", _F, 0.07, 0.05, 0.5),
    ParamSpec("BAT_EMERGEN_THR", _F, 0.05, 0.03, 0.5),
    ParamSpec("BAT_LOW_THR", _F, 0.15, 0.12, 0.5),
    ParamSpec("COM_ARM_WO_GPS", _I, 1, 0, 2),
    ParamSpec("COM_DISARM_LAND", _F, 2.0, -1.0, 20.0),
    ParamSpec("COM_DISARM_PRFLT", _F, 10.0, -1.0, 30.0),
    ParamSpec("COM_DL_LOSS_T", _I, 10, 5, 300),
    ParamSpec("COM_LOW_BAT_ACT", _I, 0, 0, 3),
    ParamSpec("COM_OBL_RC_ACT", _I, 0, 0, 7),
    ParamSpec("COM_OF_LOSS_T", _F, 1.0, 0.0, 60.0),
    ParamSpec("COM_WIND_MAX", _F, -1.0, -1.0, 30.0),
    ParamSpec("COM_WIND_WARN", _F, -1.0, -1.0, 30.0),
    ParamSpec("MAV_SIGN_CFG", _I, 0, 0, 2),
    ParamSpec("MAV_SYS_ID", _I, 1, 1, 250),
    ParamSpec("MIS_TAKEOFF_ALT", _F, 2.5, 0.0, 1000.0),
    ParamSpec("MPC_ACC_HOR", _F, 3.0, 2.0, 15.0),
    ParamSpec("MPC_ACC_UP_MAX", _F, 4.0, 1.0, 15.0),
    ParamSpec("MPC_LAND_SPEED", _F, 0.7, 0.6, 10.0),
    ParamSpec("MPC_TILTMAX_AIR", _F, 45.0, 20.0, 89.0),
    ParamSpec("MPC_TKO_SPEED", _F, 1.5, 1.0, 5.0),
    ParamSpec("MPC_XY_CRUISE", _F, 5.0, 3.0, 20.0),
    ParamSpec("MPC_XY_P", _F, 0.95, 0.0, 2.0),
    ParamSpec("MPC_XY_VEL_I_ACC", _F, 0.4, 0.0, 60.0),
    ParamSpec("MPC_XY_VEL_MAX", _F, 12.0, 0.0, 20.0),
    ParamSpec("MPC_XY_VEL_P_ACC", _F, 1.8, 1.2, 5.0),
    ParamSpec("MPC_YAWRAUTO_MAX", _F, 45.0, 5.0, 360.0),
    ParamSpec("MPC_Z_P", _F, 1.0, 0.1, 1.5),
    ParamSpec("MPC_Z_VEL_I_ACC", _F, 2.0, 0.2, 3.0),
    ParamSpec("MPC_Z_VEL_MAX_DN", _F, 1.5, 0.5, 4.0),
    ParamSpec("MPC_Z_VEL_MAX_UP", _F, 3.0, 0.5, 8.0),
    ParamSpec("MPC_Z_VEL_P_ACC", _F, 4.0, 2.0, 15.0),
    ParamSpec("NAV_DLL_ACT", _I, 0, 0, 6),
    ParamSpec("RTL_RETURN_ALT", _F, 60.0, 0.0, 150.0),
    ParamSpec("SIM_BAT_DRAIN", _F, 1200.0, 1.0, 86400.0),
    ParamSpec("SIM_BAT_MIN_PCT", _F, 50.0, 0.0, 100.0),
)

PARAM_SPECS: dict[str, ParamSpec] = {p.name: p for p in PARAM_TABLE}
PARAM_INDEX: dict[str, int] = {p.name: i for i, p in enumerate(PARAM_TABLE)}


class ParamError(ValueError):
    """A parameter name or value PX4 would not take; the message names the parameter."""


def encode_param_value(value: float, param_type: ParamType) -> float:
    """The float that carries ``value`` on the wire: bytewise for INT32, plain for REAL32."""
    if param_type == ParamType.INT32:
        return struct.unpack("<f", struct.pack("<i", int(value)))[0]
    return float(value)


def decode_param_value(wire_value: float, wire_type: int, param_type: ParamType) -> float:
    """The parameter value a PARAM_SET means; raises ParamError for NaN/inf or a value that is no integer.

    INT32 parameters arrive bytewise (PX4, MAVSDK, QGroundControl). A client that sends an INT32 parameter as a
    REAL32 number with an integral value (pymavlink's ``param_set_send`` default) is understood too.
    """
    if param_type == ParamType.INT32:
        if wire_type == ParamType.REAL32 and math.isfinite(wire_value) and float(wire_value).is_integer():
            return float(int(wire_value))
        return float(struct.unpack("<i", struct.pack("<f", wire_value))[0])
    if not math.isfinite(wire_value):
        raise ParamError("value is not finite")
    return float(wire_value)


class ParamStore:
    """The current values of :data:`PARAM_TABLE` for one vehicle (plain data, no I/O).

    ``version`` counts successful sets, so callers can cache what they derive from the values.
    """

    def __init__(self, overrides: Mapping[str, float] | None = None) -> None:
        self._values: dict[str, float] = {p.name: float(p.default) for p in PARAM_TABLE}
        self.version = 0
        for name, value in (overrides or {}).items():
            self.set(name, value)

    def __getitem__(self, name: str) -> float:
        return self._values[name]

    def get_int(self, name: str) -> int:
        """The value of an INT32 parameter as an int."""
        return int(self._values[name])

    def __len__(self) -> int:
        return len(self._values)

    def set(self, name: str, value: float) -> float:
        """Set a parameter after checking name, finiteness and range; returns the stored value."""
        spec = PARAM_SPECS.get(name)
        if spec is None:
            raise ParamError(f"{name}: unknown parameter")
        value = float(value)
        if not math.isfinite(value):
            raise ParamError(f"{name}: value is not finite")
        if spec.type == ParamType.INT32 and not value.is_integer():
            raise ParamError(f"{name}: INT32 parameter needs an integer, got {value}")
        if not spec.min_value <= value <= spec.max_value:
            raise ParamError(f"{name}: {value} outside [{spec.min_value}, {spec.max_value}]")
        self._values[name] = value
        self.version += 1
        return value

    def items(self) -> list[tuple[str, float]]:
        """(name, value) in table order, the order PARAM_VALUE indices follow."""
        return [(p.name, self._values[p.name]) for p in PARAM_TABLE]
