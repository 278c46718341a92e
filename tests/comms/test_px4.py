"""PX4 mode table: custom_mode encoding from PX4_INTERFACE.md, base_mode flags, requirements."""

import pytest

from comms.px4 import (
    MODE_TABLE,
    Px4Mode,
    base_mode,
    custom_mode,
    mode_allowed,
    mode_from_custom_mode,
    mode_from_numbers,
)

EXPECTED = {
    Px4Mode.MANUAL: (1, 0),
    Px4Mode.ALTCTL: (2, 0),
    Px4Mode.POSCTL: (3, 0),
    Px4Mode.OFFBOARD: (6, 0),
    Px4Mode.STABILIZED: (7, 0),
    Px4Mode.AUTO_READY: (4, 1),
    Px4Mode.AUTO_TAKEOFF: (4, 2),
    Px4Mode.AUTO_LOITER: (4, 3),
    Px4Mode.AUTO_MISSION: (4, 4),
    Px4Mode.AUTO_RTL: (4, 5),
    Px4Mode.AUTO_LAND: (4, 6),
}


@pytest.mark.parametrize("mode", list(Px4Mode))
def test_custom_mode_encoding_matches_px4(mode: Px4Mode) -> None:
    main, sub = EXPECTED[mode]
    assert custom_mode(mode) == (sub << 24) | (main << 16)
    assert mode_from_custom_mode(custom_mode(mode)) is mode
    assert mode_from_numbers(main, sub) is mode


def test_known_wire_values() -> None:
    assert custom_mode(Px4Mode.OFFBOARD) == 393216
    assert custom_mode(Px4Mode.AUTO_LOITER) == 50593792
    assert custom_mode(Px4Mode.AUTO_TAKEOFF) == 33816576


@pytest.mark.parametrize("value", [0, 5 << 16, (4 << 16) | (9 << 24), (6 << 16) | 1, -1, 8 << 16])
def test_undefined_custom_modes_are_none(value: int) -> None:
    assert mode_from_custom_mode(value) is None


def test_non_auto_main_mode_ignores_sub_mode() -> None:
    assert mode_from_numbers(6, 3) is Px4Mode.OFFBOARD
    assert mode_from_numbers(4, 0) is None


def test_base_mode_flags() -> None:
    assert base_mode(Px4Mode.AUTO_LOITER, armed=False) == 1 | 4 | 8 | 16
    assert base_mode(Px4Mode.OFFBOARD, armed=True) == 128 | 1 | 4 | 8 | 16
    assert base_mode(Px4Mode.POSCTL, armed=False) == 1 | 64 | 16 | 8
    assert base_mode(Px4Mode.MANUAL, armed=False) & 64
    for mode in Px4Mode:
        assert base_mode(mode, False) & 1


def test_requirements() -> None:
    assert mode_allowed(Px4Mode.OFFBOARD, True, False)
    assert not mode_allowed(Px4Mode.OFFBOARD, False, False)
    assert not mode_allowed(Px4Mode.AUTO_RTL, True, False)
    assert mode_allowed(Px4Mode.AUTO_RTL, True, True)
    assert mode_allowed(Px4Mode.STABILIZED, False, False)
    assert all(spec.manual == (m in (Px4Mode.MANUAL, Px4Mode.ALTCTL, Px4Mode.POSCTL, Px4Mode.STABILIZED)) for m, spec in MODE_TABLE.items())
