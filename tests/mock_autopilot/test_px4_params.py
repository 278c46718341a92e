"""Parameter table, PX4 types and the bytewise INT32 wire encoding."""

import math
import struct

import pytest

from mock_autopilot.px4_params import (
    PARAM_SPECS,
    PARAM_TABLE,
    ParamError,
    ParamStore,
    ParamType,
    decode_param_value,
    encode_param_value,
)

REQUIRED = [
    "MIS_TAKEOFF_ALT", "COM_OF_LOSS_T", "COM_OBL_RC_ACT", "COM_DISARM_LAND", "COM_DISARM_PRFLT", "MPC_XY_VEL_MAX",
    "MPC_Z_VEL_MAX_UP", "MPC_Z_VEL_MAX_DN", "MPC_LAND_SPEED", "MPC_ACC_HOR", "NAV_DLL_ACT", "RTL_RETURN_ALT", "MAV_SYS_ID",
]


def test_required_parameters_with_px4_types() -> None:
    for name in REQUIRED:
        assert name in PARAM_SPECS
    ints = {"COM_OBL_RC_ACT", "NAV_DLL_ACT", "MAV_SYS_ID"}
    for name in REQUIRED:
        assert PARAM_SPECS[name].type == (ParamType.INT32 if name in ints else ParamType.REAL32), name
    assert len({p.name for p in PARAM_TABLE}) == len(PARAM_TABLE)
    assert all(len(p.name) <= 16 for p in PARAM_TABLE)


def test_defaults_are_px4_defaults() -> None:
    store = ParamStore()
    assert store["MIS_TAKEOFF_ALT"] == 2.5
    assert store["COM_OF_LOSS_T"] == 1.0
    assert store["COM_DISARM_LAND"] == 2.0
    assert store["MPC_XY_VEL_MAX"] == 12.0
    for p in PARAM_TABLE:
        assert p.min_value <= p.default <= p.max_value, p.name


@pytest.mark.parametrize("value", [0, 1, 7, 250, 10015, -1, 2**31 - 1])
def test_int32_bytewise_roundtrip(value: int) -> None:
    wire = encode_param_value(value, ParamType.INT32)
    packed = struct.pack("<f", wire)
    assert struct.unpack("<i", packed)[0] == value
    assert decode_param_value(wire, ParamType.INT32, ParamType.INT32) == value


def test_int32_sent_as_real32_integer_is_understood() -> None:
    assert decode_param_value(4.0, ParamType.REAL32, ParamType.INT32) == 4


def test_real32_passes_through_and_rejects_non_finite() -> None:
    assert encode_param_value(2.5, ParamType.REAL32) == 2.5
    assert decode_param_value(7.25, ParamType.REAL32, ParamType.REAL32) == 7.25
    for bad in (math.nan, math.inf, -math.inf):
        with pytest.raises(ParamError):
            decode_param_value(bad, ParamType.REAL32, ParamType.REAL32)


def test_store_checks_name_range_type_and_finiteness() -> None:
    store = ParamStore({"MIS_TAKEOFF_ALT": 10.0})
    assert store["MIS_TAKEOFF_ALT"] == 10.0
    with pytest.raises(ParamError, match="UNKNOWN_P"):
        store.set("UNKNOWN_P", 1)
    with pytest.raises(ParamError, match="COM_OBL_RC_ACT"):
        store.set("COM_OBL_RC_ACT", 9)
    with pytest.raises(ParamError):
        store.set("COM_OBL_RC_ACT", 1.5)
    with pytest.raises(ParamError):
        store.set("MPC_XY_VEL_MAX", math.nan)
    assert store.set("COM_OBL_RC_ACT", 4) == 4
    assert store.get_int("COM_OBL_RC_ACT") == 4
    assert [n for n, _ in store.items()] == [p.name for p in PARAM_TABLE]
