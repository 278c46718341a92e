"""Checks of the live map's command-line values, shared by ``gcs.mission`` and ``gcs.dashboard`` (pure)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

TILE_SUFFIXES = (".mbtiles", ".pmtiles")


def check_dashboard_args(port: int, token: str | None, tiles: Path | None, fail: Callable[[str], None]) -> None:
    """Call ``fail`` with one line naming the flag for the first bad value (a port, an empty token, a tiles file
    that is missing or of another kind)."""
    if not 0 <= port <= 65535:
        fail(f"--dashboard-port: must be 0-65535, got {port}")
    if token is not None and not token.strip():
        fail("--dashboard-token: must not be empty")
    if tiles is not None:
        if tiles.suffix.lower() not in TILE_SUFFIXES:
            fail(f"--tiles: {tiles} is neither .mbtiles nor .pmtiles")
        elif not tiles.is_file():
            fail(f"--tiles: no such file {tiles}")
