"""Rows on disk (atomic, one file per run, read back as one table) and the progress text."""

from pathlib import Path

from gcs.campaign.progress import Counts, eta_s, format_duration, status_text
from gcs.campaign.store import done_run_ids, read_rows, write_row


def test_rows_round_trip_with_differing_columns(tmp_path: Path) -> None:
    write_row(tmp_path, "b", {"run_id": "b", "seed": 2, "coverage_final": 0.5, "error": None})
    write_row(tmp_path, "a", {"run_id": "a", "seed": 1, "coverage_final": None, "error": "ValueError: x"})
    write_row(tmp_path, "c", {"run_id": "c", "seed": 3, "extra": "y"})
    (tmp_path / "rows" / ".d.123.tmp").write_bytes(b"half a file")
    assert done_run_ids(tmp_path) == {"a", "b", "c"}
    rows = read_rows(tmp_path)
    assert [r["run_id"] for r in rows] == ["a", "b", "c"]
    assert rows[0]["error"] == "ValueError: x" and rows[1]["coverage_final"] == 0.5 and rows[2]["extra"] == "y"
    assert rows[2]["coverage_final"] is None
    assert done_run_ids(tmp_path / "nothing") == set() and read_rows(tmp_path / "nothing") == []


def test_rewriting_a_row_replaces_it(tmp_path: Path) -> None:
    write_row(tmp_path, "a", {"run_id": "a", "wall_s": 1.0})
    write_row(tmp_path, "a", {"run_id": "a", "wall_s": 2.0})
    assert read_rows(tmp_path) == [{"run_id": "a", "wall_s": 2.0}]
    assert sorted(p.name for p in (tmp_path / "rows").iterdir()) == ["a.parquet"]


def test_progress_text_and_eta() -> None:
    counts = Counts(total=40, done=10, failed=1, running=2, skipped=5)
    assert eta_s(counts, 100.0) == 300.0
    assert eta_s(Counts(40, 0, 0, 2), 100.0) is None
    assert status_text(counts, 100.0) == "10/40 done, 2 running, 1 failed, ETA 5:00, 5 already done"
    assert format_duration(3725) == "1:02:05" and format_duration(None) == "?"
