"""The import rules between FloodWatch's packages, checked from the source with ``ast`` (every .py file, imports
inside functions included):

- ``mission_plan`` is a leaf: it imports none of the other four;
- ``comms`` imports none of ``gcs``, ``vehicle_agents``, ``mock_autopilot``;
- ``vehicle_agents`` and ``mock_autopilot`` never import ``gcs`` (a drone's onboard computer and the simulator do
  not depend on the ground station);
- the package-level import graph has no cycle.
"""

from __future__ import annotations

import ast
from collections.abc import Iterable, Mapping
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PACKAGES = ("mission_plan", "comms", "vehicle_agents", "mock_autopilot", "gcs")
FORBIDDEN: dict[str, frozenset[str]] = {
    "mission_plan": frozenset({"comms", "vehicle_agents", "mock_autopilot", "gcs"}),
    "comms": frozenset({"vehicle_agents", "mock_autopilot", "gcs"}),
    "vehicle_agents": frozenset({"gcs"}),
    "mock_autopilot": frozenset({"gcs"}),
    "gcs": frozenset(),
}


def imported_top_levels(source: str, module: str) -> set[str]:
    """Top-level names of every module ``source`` imports (relative imports resolve inside ``module``'s package)."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            names.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                names.add(module.split(".")[0])
            elif node.module:
                names.add(node.module.split(".")[0])
    return names


def package_imports(root: Path, packages: Iterable[str]) -> dict[str, dict[str, set[Path]]]:
    """For each package under ``root``: the other packages it imports, and from which files."""
    graph: dict[str, dict[str, set[Path]]] = {}
    for package in packages:
        edges: dict[str, set[Path]] = {}
        for path in sorted((root / package).rglob("*.py")):
            module = ".".join(path.relative_to(root).with_suffix("").parts)
            for target in imported_top_levels(path.read_text(encoding="utf-8"), module):
                if target in packages and target != package:
                    edges.setdefault(target, set()).add(path.relative_to(root))
        graph[package] = edges
    return graph


def rule_violations(graph: Mapping[str, Mapping[str, set[Path]]], forbidden: Mapping[str, frozenset[str]]) -> list[str]:
    """One line per forbidden import: ``package -> target (file, ...)``."""
    return [f"{package} imports {target} ({', '.join(sorted(map(str, files)))})"
            for package, edges in sorted(graph.items()) for target, files in sorted(edges.items())
            if target in forbidden.get(package, frozenset())]


def find_cycle(graph: Mapping[str, Mapping[str, object]]) -> list[str] | None:
    """A cycle of the package graph as ``[a, b, ..., a]``, or None when it is acyclic (depth-first search)."""
    state: dict[str, str] = {}
    stack: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = "open"
        stack.append(node)
        for target in sorted(graph.get(node, {})):
            if state.get(target) == "open":
                return [*stack[stack.index(target):], target]
            if target not in state:
                cycle = visit(target)
                if cycle is not None:
                    return cycle
        stack.pop()
        state[node] = "done"
        return None

    for node in sorted(graph):
        if node not in state:
            cycle = visit(node)
            if cycle is not None:
                return cycle
    return None


def test_packages_import_only_what_the_rules_allow() -> None:
    graph = package_imports(REPO, PACKAGES)
    assert rule_violations(graph, FORBIDDEN) == []


def test_no_import_cycle_between_packages() -> None:
    assert find_cycle(package_imports(REPO, PACKAGES)) is None


def _write(root: Path, relative: str, source: str) -> None:
    path = root / relative
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(source, encoding="utf-8")


def test_the_checker_sees_function_level_and_from_imports_and_cycles(tmp_path: Path) -> None:
    """The checker itself can fail: a synthetic tree breaking each rule is caught."""
    for package in PACKAGES:
        _write(tmp_path, f"{package}/__init__.py", "")
    _write(tmp_path, "mission_plan/plans.py", "import numpy\nfrom comms.frames import enu_to_ned\n")
    _write(tmp_path, "vehicle_agents/deep/agent.py", "def main():\n    from gcs.scenario import load_scenario\n")
    _write(tmp_path, "mock_autopilot/cli.py", "import gcs.mission.cli as cli\nfrom . import fleet\n")
    graph = package_imports(tmp_path, PACKAGES)
    violations = rule_violations(graph, FORBIDDEN)
    assert violations == [
        f"mission_plan imports comms ({Path('mission_plan/plans.py')})",
        f"mock_autopilot imports gcs ({Path('mock_autopilot/cli.py')})",
        f"vehicle_agents imports gcs ({Path('vehicle_agents/deep/agent.py')})",
    ]
    assert find_cycle(graph) is None
    _write(tmp_path, "gcs/engine.py", "from vehicle_agents.deep import agent\n")
    assert find_cycle(package_imports(tmp_path, PACKAGES)) == ["gcs", "vehicle_agents", "gcs"]


@pytest.mark.parametrize(("graph", "cycle"), [
    ({"a": {"b": 1}, "b": {"c": 1}, "c": {}}, None),
    ({"a": {"b": 1}, "b": {"c": 1}, "c": {"a": 1}}, ["a", "b", "c", "a"]),
    ({"a": {}, "b": {"b": 1}}, ["b", "b"]),
])
def test_find_cycle(graph: dict[str, dict[str, int]], cycle: list[str] | None) -> None:
    assert find_cycle(graph) == cycle
