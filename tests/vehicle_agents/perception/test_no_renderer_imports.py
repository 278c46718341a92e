"""Perception is onboard code: it reads images, never the simulator. No module of ``vehicle_agents.perception``
imports ``mock_autopilot`` (the renderer's colours, textures or constants) or anything that does."""

from __future__ import annotations

import ast
from pathlib import Path

PERCEPTION = Path(__file__).resolve().parents[3] / "vehicle_agents" / "perception"
ALLOWED_PROJECT_IMPORTS = ("vehicle_agents.perception", "comms.camera_projection", "comms.frames")


def project_imports(path: Path) -> set[str]:
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
    return {n for n in names if n.split(".")[0] in ("mock_autopilot", "gcs", "vehicle_agents", "comms",
                                                    "mission_plan")}


def test_perception_imports_nothing_of_the_simulator() -> None:
    files = sorted(PERCEPTION.glob("*.py"))
    assert files
    for path in files:
        for name in project_imports(path):
            assert name.startswith(ALLOWED_PROJECT_IMPORTS), f"{path.name} imports {name}"
