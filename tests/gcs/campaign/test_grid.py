"""Campaign arguments as pure values: seeds, modes, grid axes, the run list and stable run ids."""

import pytest

from gcs.campaign.grid import (
    CampaignSyntaxError,
    GridAxis,
    Mode,
    RunSpec,
    check_axes,
    expand,
    grid_cells,
    parse_grid_axis,
    parse_modes,
    parse_seeds,
    run_id,
)
from mission_plan.control_params import MODES


def test_seeds_ranges_lists_and_repeats() -> None:
    assert parse_seeds("1-20") == tuple(range(1, 21))
    assert parse_seeds("3") == (3,)
    assert parse_seeds("9-10, 1,4,4") == (1, 4, 9, 10)


@pytest.mark.parametrize("text", ["", "a", "1-", "5-2", "-3", "1..4", "1-2-3", "1,,2"])
def test_bad_seeds_name_the_argument(text: str) -> None:
    with pytest.raises(CampaignSyntaxError, match="--seeds"):
        parse_seeds(text)


def test_modes_are_the_control_modes() -> None:
    assert {m.value for m in Mode} == set(MODES)
    assert parse_modes("improved,paper,improved") == (Mode.IMPROVED, Mode.PAPER)
    with pytest.raises(CampaignSyntaxError, match="--mode 'papr'"):
        parse_modes("paper,papr")


def test_grid_axis_values_split_outside_brackets() -> None:
    assert parse_grid_axis("radio.loss=0,0.3") == GridAxis("radio.loss", ("0", "0.3"))
    assert parse_grid_axis("flood.velocity_en_mps=[1, 2],[3,4]").values == ("[1, 2]", "[3,4]")
    assert parse_grid_axis('control.pdot_reading="full",none').values == ('"full"', "none")


@pytest.mark.parametrize("text", ["radio.loss", "=1", "radio.loss=", "radio.loss=0,,1", "radio..loss=1",
                                  "radio.loss=1,1", "seed=1,2"])
def test_bad_grid_axes(text: str) -> None:
    with pytest.raises(CampaignSyntaxError, match="--grid"):
        parse_grid_axis(text)


def test_a_key_in_two_places_is_refused() -> None:
    axes = [parse_grid_axis("radio.loss=0,1")]
    with pytest.raises(CampaignSyntaxError, match="given twice"):
        check_axes(axes * 2, [])
    with pytest.raises(CampaignSyntaxError, match="also given with --set"):
        check_axes(axes, ["radio.loss=0.5"])
    with pytest.raises(CampaignSyntaxError, match="--set seed"):
        check_axes([], ["seed=3"])


def test_every_combination_once() -> None:
    axes = [parse_grid_axis("radio.loss=0,0.3"), parse_grid_axis("radio.latency_s=0,0.2")]
    cells = grid_cells(axes)
    assert len(cells) == 4 and cells[1] == (("radio.loss", "0"), ("radio.latency_s", "0.2"))
    assert grid_cells([]) == [()]
    runs = expand("circle", [Mode.IMPROVED, Mode.PAPER], parse_seeds("1-20"), axes, ["duration_s=5"])
    assert len(runs) == 20 * 2 * 4 and len({r.run_id for r in runs}) == len(runs)
    assert runs[0].overrides() == ["duration_s=5", "radio.loss=0", "radio.latency_s=0", "seed=1"]


def test_run_id_is_stable_and_ignores_flag_order() -> None:
    a = RunSpec("circle", Mode.PAPER, 3, (("radio.loss", "0.3"), ("radio.latency_s", "0")), ("duration_s=5",))
    b = RunSpec("circle", Mode.PAPER, 3, (("radio.latency_s", "0"), ("radio.loss", "0.3")), ("duration_s=5",))
    assert run_id(a) == run_id(b) == a.run_id
    assert run_id(a) == "645a86bda6f49e02"  # fixed: a rerun on any machine finds the rows of earlier runs
    others = [RunSpec("circle", Mode.IMPROVED, 3, a.cell, a.fixed), RunSpec("circle", Mode.PAPER, 4, a.cell, a.fixed),
              RunSpec("ellipse", Mode.PAPER, 3, a.cell, a.fixed), RunSpec("circle", Mode.PAPER, 3, a.cell, ()),
              RunSpec("circle", Mode.PAPER, 3, (("radio.loss", "0.31"), ("radio.latency_s", "0")), a.fixed)]
    assert len({run_id(o) for o in others} | {run_id(a)}) == 6
