"""docs/RESULTS.md from campaign rows (pure rendering; nothing is run)."""

from pathlib import Path

from gcs.campaign.results_doc import CAMPAIGNS, NOTHING_MOVED, main, render, seed_spread
from gcs.campaign.store import write_row


def _row(mode: str, seed: int, **metrics: object) -> dict:
    base = {"run_id": f"{mode}{seed}", "scenario": "circle", "mode": mode, "seed": seed, "error": None,
            "vehicles": 13, "code_version": "abc123", "wall_s": 20.0, "encircle_time_s": 10.9,
            "spacing_cv_final": 0.001, "polygon_iou_final": 0.998, "min_pairwise_distance_m": 1.48}
    return {**base, **metrics}


def test_calm_seeds_are_called_what_they_are() -> None:
    rows = [_row("improved", s) for s in range(1, 21)]
    assert seed_spread(rows) == NOTHING_MOVED
    moved = rows[:-1] + [_row("improved", 20, polygon_iou_final=0.990)]
    assert seed_spread(moved) == "polygon IoU 0.000 (max - min 0.008)"


def test_render_targets_distributions_and_commands() -> None:
    circle = [_row("improved", s) for s in range(1, 21)] + [_row("paper", s, encircle_time_s=21.2 + s / 100)
                                                           for s in range(1, 21)]
    circle.append(_row("paper", 21, error="OverflowError: x"))
    pdot = [_row(mode, s, **{"grid:control.pdot_reading": reading, "cell": f"control.pdot_reading={reading}"})
            for mode in ("paper", "improved") for s in (1, 2) for reading in ("full", "none")]
    text = render({"circle": circle, "circle-pdot": pdot}, "2026-01-01 00:00 UTC")
    assert "python -m gcs.campaign circle --seeds 1-20 --mode paper,improved --workers 1 --out runs/results/circle" \
        in text
    assert "--grid control.pdot_reading=full,none" in text
    assert "| T_enc [s] | <= 20 | 21.3 [21.2, 21.4] | 0.2 | 10.9 | 0.0 | yes (20/20 runs) |" in text
    assert "| `circle` | 40 | 41 | 1 | 20 | abc123 |" in text and "| `large` | 10 | 0 | 0 | — | — |" in text
    assert "| improved | full | 2 of 20 |" in text and "| paper | normal (default) | 20 |" in text
    assert NOTHING_MOVED in text and "OverflowError: x" in text
    assert len(CAMPAIGNS) == 17
    assert ("python -m gcs.campaign circle --seeds 1-20 --mode paper,improved --set weather=moderate --workers 1 "
            "--out runs/results/circle-weather-moderate") in text


def test_the_hydro_section_scores_the_caged_component_against_its_targets() -> None:
    breach = [_row("improved", 1, scenario="breach", polygon_iou_final=0.983, min_pairwise_distance_m=1.32,
                   caged_area_fraction_final=1.0, edge_speed_p50_mps=0.075),
              _row("paper", 1, scenario="breach", polygon_iou_final=0.857, min_pairwise_distance_m=0.08)]
    river = [_row("improved", 1, scenario="river", polygon_iou_final=0.93, min_pairwise_distance_m=1.2)]
    text = render({"breach": breach, "river": river}, "2026-01-01 00:00 UTC")
    assert "## Hydrodynamic floods (ANUGA)" in text
    assert "| `breach` | improved | 1 | 0.983 | 1.32 |" in text and "| 1.00 | 0.075 |" in text
    lines = {line.split(" | ")[0] + line.split(" | ")[1]: line for line in text.splitlines() if line.startswith("| `")}
    assert lines["| `breach`improved"].endswith("yes (1/1 runs) |")
    assert lines["| `river`improved"].endswith("no (0/1 runs) |")  # IoU below 0.95
    assert lines["| `pluvial`improved"].endswith("(not a target) |")


def test_main_reads_rows_from_the_campaign_folders(tmp_path: Path) -> None:
    for row in [_row("improved", 1), _row("paper", 1)]:
        write_row(tmp_path / "circle", row["run_id"], row)
    out = tmp_path / "RESULTS.md"
    assert main(["--root", str(tmp_path), "--out", str(out)]) == 0
    assert "| `circle` | 40 | 2 | 0 | 20 | abc123 |" in out.read_text()


def test_report_rewrites_summary_and_plots_from_rows_alone(tmp_path: Path) -> None:
    from gcs.campaign.cli import main as campaign_main

    camp = tmp_path / "camp"
    for loss in ("0", "0.3"):
        for row in [_row("improved", 1), _row("paper", 1)]:
            row.update({"run_id": f"{row['run_id']}-{loss}", "cell": f"radio.loss={loss}", "grid:radio.loss": loss})
            write_row(camp, row["run_id"], row)
    assert campaign_main(["report", str(camp)]) == 0
    assert "| T_enc [s] | radio.loss=0.3 | 1 | 10.9 |" in (camp / "summary.md").read_text()
    assert (camp / "plots" / "circle__polygon_iou_final__radio.loss.png").stat().st_size > 1000
    assert campaign_main(["report", str(tmp_path / "none")]) == 2
