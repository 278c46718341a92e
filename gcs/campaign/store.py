"""A campaign's rows on disk: one small Parquet file per finished run, read back as one table.

A row file appears whole or not at all (written to a temporary name in the same folder, then renamed), so an
interrupted campaign leaves only complete rows, and the set of file names is the set of runs already done.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq

ROWS_DIR = "rows"
SUFFIX = ".parquet"


def rows_dir(out_dir: Path) -> Path:
    return out_dir / ROWS_DIR


def write_row(out_dir: Path, run_id: str, row: dict[str, Any]) -> Path:
    """Write ``<out>/rows/<run_id>.parquet`` atomically and return its path."""
    folder = rows_dir(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    target = folder / f"{run_id}{SUFFIX}"
    table = pa.Table.from_pylist([row])
    fd, tmp_name = tempfile.mkstemp(prefix=f".{run_id}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as handle:
            pq.write_table(table, handle)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp_name, target)
    except BaseException:
        Path(tmp_name).unlink(missing_ok=True)
        raise
    return target


def done_run_ids(out_dir: Path) -> set[str]:
    """The run ids that have a row (a failed run's row counts: rerunning it would fail the same way)."""
    folder = rows_dir(out_dir)
    if not folder.is_dir():
        return set()
    return {path.name[: -len(SUFFIX)] for path in folder.glob(f"*{SUFFIX}") if not path.name.startswith(".")}


def read_table(out_dirs: Iterable[Path]) -> pa.Table:
    """Every row under the given campaign folders as one table (columns a row lacks are null there)."""
    tables = [pq.read_table(path) for out_dir in out_dirs
              for path in sorted(rows_dir(out_dir).glob(f"*{SUFFIX}")) if not path.name.startswith(".")]
    if not tables:
        return pa.table({})
    return pa.concat_tables(tables, promote_options="permissive")


def read_rows(*out_dirs: Path) -> list[dict[str, Any]]:
    """The rows as plain dicts, in run-id order within each folder."""
    return read_table(out_dirs).to_pylist()
