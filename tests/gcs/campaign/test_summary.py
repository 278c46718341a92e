"""Campaign statistics and summary.md, from rows alone (pure)."""

import math

import pytest

from gcs.campaign.summary import Stats, distribution, format_stats, metric_columns, summary_markdown


def test_distribution_interpolates_percentiles_and_counts_missing() -> None:
    stats = distribution([*range(1, 21), None, math.nan, "text"])
    assert (stats.n, stats.missing) == (20, 3)
    assert stats.mean == pytest.approx(10.5)
    assert (stats.p5, stats.p50, stats.p95) == pytest.approx((1.95, 10.5, 19.05))
    assert stats.spread == pytest.approx(17.1)


def test_one_value_and_no_value() -> None:
    assert distribution([2.5]) == Stats(1, 2.5, 2.5, 2.5, 2.5)
    empty = distribution([None, None])
    assert empty.n == 0 and empty.missing == 2 and math.isnan(empty.p50)
    assert format_stats(empty) == "—"
    assert format_stats(distribution([3.0, 3.0])) == "3"
    assert format_stats(distribution([1.0, 2.0, 3.0])) == "2 [1.1, 2.9]"


def _row(mode: str, seed: int, loss: str, iou: float | None, error: str | None = None) -> dict:
    return {"run_id": f"{mode}{seed}{loss}", "scenario": "circle", "mode": mode, "seed": seed,
            "cell": f"radio.loss={loss}", "grid:radio.loss": loss, "error": error, "polygon_iou_final": iou,
            "wall_s": 1.0}


def test_summary_puts_modes_side_by_side_per_cell_and_lists_failures() -> None:
    rows = [_row(mode, seed, loss, 0.9 + seed / 100)
            for mode in ("improved", "paper") for seed in (1, 2, 3) for loss in ("0.3", "0")]
    rows.append(_row("paper", 4, "0", None, error="OverflowError: boom"))
    text = summary_markdown(rows)
    assert "13 runs: 12 ok, 1 failed" in text
    assert "| metric | grid cell | paper n | paper mean | paper p5 | paper p50 | paper p95 | improved n |" in text
    table = [line for line in text.splitlines() if line.startswith("| polygon IoU |")]
    assert [line.split(" | ")[1] for line in table] == ["radio.loss=0", "radio.loss=0.3"]
    assert table[0].split(" | ")[2:7] == ["3", "0.92", "0.911", "0.92", "0.929"]
    assert "| paper4" in text and "OverflowError: boom" in text


def test_metric_columns_headline_first_then_other_numbers() -> None:
    rows = [{"seed": 1, "wall_s": 2.0, "coverage_final": 0.9, "zeta": 1, "note": "x", "grid:radio.loss": "0"}]
    assert [k for k, _ in metric_columns(rows)] == ["coverage_final", "wall_s", "zeta"]
