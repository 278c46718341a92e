"""The weather section of RESULTS.md from rows (pure)."""

from __future__ import annotations

from gcs.campaign.results_weather import path_ratios, weather_campaign, weather_section


def _row(seed: int, mode: str, path_m: float, iou: float = 0.99, min_pair_m: float = 1.3) -> dict[str, object]:
    return {"seed": seed, "mode": mode, "path_length_total_m": path_m, "polygon_iou_final": iou,
            "coverage_final": 0.97, "spacing_cv_final": 0.02, "min_pairwise_distance_m": min_pair_m}


def test_the_path_ratio_pairs_each_seed_with_its_own_calm_run() -> None:
    calm = [_row(1, "improved", 100.0), _row(2, "improved", 200.0), _row(1, "paper", 999.0)]
    moderate = [_row(1, "improved", 110.0), _row(2, "improved", 200.0), _row(3, "improved", 50.0)]
    assert path_ratios(moderate, calm) == {1: 1.1, 2: 1.0}


def test_the_section_counts_seeds_missing_close_pairs_and_the_ratio() -> None:
    rows = {
        weather_campaign("calm"): [_row(s, "improved", 100.0) for s in (1, 2)],
        weather_campaign("moderate"): [_row(1, "improved", 120.0, min_pair_m=0.8), _row(2, "improved", 101.0)],
    }
    text = "\n".join(weather_section(rows, planned_seeds=20))
    assert "| `moderate` | improved | 2 of 20 |" in text
    assert "| `rough` | paper | 0 of 20 |" in text
    assert "at least 1.05x in 1 of 2 seeds" in text
    assert "| min pair [m] | min | >= 1 | 0.80 | no |" in text
