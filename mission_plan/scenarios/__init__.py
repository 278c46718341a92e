"""The bundled scenarios: ``circle``, ``ellipse``, ``nonconvex``, ``drift``, ``terrain``, ``large`` (TOML files)."""

from __future__ import annotations

from pathlib import Path

SCENARIO_DIR = Path(__file__).resolve().parent


def scenario_names() -> list[str]:
    """Names of the bundled scenarios."""
    return sorted(p.stem for p in SCENARIO_DIR.glob("*.toml"))
