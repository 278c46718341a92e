"""The radio part of docs/RESULTS.md: cells from the loss grid and the burst campaigns, and the target check."""

from gcs.campaign.results_doc import CAMPAIGNS
from gcs.campaign.results_radio import LOSS_CAMPAIGN, burst_campaign, radio_section


def _row(seed: int, **metrics: object) -> dict:
    base = {"run_id": f"r{seed}", "mode": "improved", "seed": seed, "error": None, "polygon_iou_final": 0.996,
            "coverage_final": 0.983, "spacing_cv_final": 0.0007, "min_pairwise_distance_m": 1.3, "near_miss_pairs": 0}
    return {**base, **metrics}


def test_cells_come_from_the_loss_grid_and_each_burst_campaign() -> None:
    loss = [_row(s, **{"grid:radio.loss": v}) for v in ("0", "0.5") for s in (1, 2)]
    loss.append(_row(3, **{"grid:radio.loss": "0.7", "min_pairwise_distance_m": 0.8, "near_miss_pairs": 1}))
    text = "\n".join(radio_section({LOSS_CAMPAIGN: loss, burst_campaign("2"): [_row(1)]}, 2))
    lines = {line.split(" | ")[0]: line for line in text.splitlines() if line.startswith("| ")}
    assert lines["| Bernoulli 50%"].startswith("| Bernoulli 50% | 2 | 0.996 | 0.983 | 0.0007 | 1.30 |")
    assert lines["| Bernoulli 70%"].endswith("| 0.80 | 1 |")
    assert lines["| Bernoulli 10%"].startswith("| Bernoulli 10% | 0 of 2 | — |")
    assert lines["| bursts, mean 2 s (50 % average)"].startswith("| bursts, mean 2 s (50 % average) | 1 of 2 |")


def test_the_target_cell_is_checked_against_each_statistic() -> None:
    rows = [_row(s) for s in range(1, 20)] + [_row(20, min_pairwise_distance_m=0.95, polygon_iou_final=0.90)]
    text = "\n".join(radio_section({burst_campaign("1"): rows}, 20))
    assert "| min pair [m] | min | >= 1 | 0.95 | no |" in text
    assert "| spacing CV | p95 | <= 0.1 | 0.0007 | yes |" in text
    assert "| polygon IoU | p5 | >= 0.97 | 0.991 | yes |" in text  # one bad seed of 20 sits between p0 and p5


def test_every_radio_campaign_is_listed_with_its_command() -> None:
    commands = {c.name: c.command() for c in CAMPAIGNS}
    assert "--mode improved --grid radio.loss=0,0.1,0.3,0.5,0.7 --set radio.latency_s=0.2 --set " \
           "radio.gcs_lossless=false" in commands[LOSS_CAMPAIGN]
    assert "--set radio.burst_mean_s=1 --set radio.burst_gap_s=1" in commands[burst_campaign("1")]
    assert next(c for c in CAMPAIGNS if c.name == burst_campaign("1")).planned_runs() == 20
