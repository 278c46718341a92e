"""What a campaign runs, as pure values: seeds and grid syntax, the run list, and each run's stable id.

A run is fully named by its scenario, mode, seed and the scenario overrides it applies (the grid cell's
assignments plus the campaign's fixed ``--set`` ones). The run id hashes exactly those, in a canonical order, so the
same command gives the same ids on any machine and a rerun can skip the runs whose rows already exist.
"""

from __future__ import annotations

import hashlib
import itertools
import json
from collections.abc import Sequence
from dataclasses import dataclass

from mission_plan.control_params import ControlMode

Mode = ControlMode
"""The control-law sets a run can fly."""


class CampaignSyntaxError(ValueError):
    """A seeds, grid, mode or ``--set`` argument that cannot be read; the message is one line naming it."""


RESERVED_KEYS = ("seed",)
"""Scenario keys a campaign sets itself (``--seeds``), so a grid or ``--set`` may not."""

MAX_RUNS = 100_000
"""More runs than this is a typo (``1-100000000``), not a campaign."""


@dataclass(frozen=True)
class GridAxis:
    """One ``--grid KEY=V1,V2``: a dotted scenario key and its values, as written (parsed later as TOML)."""

    key: str
    values: tuple[str, ...]


@dataclass(frozen=True)
class RunSpec:
    """One run of a campaign: scenario (bundled name or TOML path), mode, seed and its overrides."""

    scenario: str
    mode: Mode
    seed: int
    cell: tuple[tuple[str, str], ...]
    """This run's grid assignments ``(key, value)``, in the order of the ``--grid`` flags."""
    fixed: tuple[str, ...] = ()
    """The campaign's ``--set KEY=VALUE`` overrides, the same for every run."""

    def overrides(self) -> list[str]:
        """Scenario overrides for ``load_scenario``: fixed ones, then the grid cell, then the seed (last wins)."""
        return [*self.fixed, *(f"{key}={value}" for key, value in self.cell), f"seed={self.seed}"]

    def cell_label(self) -> str:
        """The grid cell as ``key=value, key=value`` (``-`` without a grid): the summary's group name."""
        return cell_label(self.cell)

    @property
    def run_id(self) -> str:
        return run_id(self)


def cell_label(cell: Sequence[tuple[str, str]]) -> str:
    """A grid cell in the ``--grid`` order, ``-`` for the empty cell."""
    return ", ".join(f"{key}={value}" for key, value in cell) or "-"


def parse_seeds(text: str) -> tuple[int, ...]:
    """``1-20``, ``3``, ``1,4,9-12`` → sorted unique non-negative seeds; raises CampaignSyntaxError."""
    seeds: set[int] = set()
    for part in text.split(","):
        part = part.strip()
        low, dash, high = part.partition("-")
        try:
            first = int(low)
            last = int(high) if dash else first
        except ValueError:
            raise CampaignSyntaxError(f"--seeds {text!r}: expected e.g. 1-20 or 1,4,9-12") from None
        if first < 0 or last < first:
            raise CampaignSyntaxError(f"--seeds {text!r}: {part!r} is not a range of seeds >= 0, low-high")
        if last - first >= MAX_RUNS:
            raise CampaignSyntaxError(f"--seeds {text!r}: more than {MAX_RUNS} seeds")
        seeds.update(range(first, last + 1))
    return tuple(sorted(seeds))


def parse_modes(text: str) -> tuple[Mode, ...]:
    """``improved,paper`` → modes in the given order, without repeats; raises CampaignSyntaxError."""
    modes: list[Mode] = []
    for part in (p.strip() for p in text.split(",")):
        try:
            mode = Mode(part)
        except ValueError:
            raise CampaignSyntaxError(
                f"--mode {part!r}: unknown mode (known: {', '.join(m.value for m in Mode)})") from None
        if mode not in modes:
            modes.append(mode)
    return tuple(modes)


def _split_values(text: str) -> list[str]:
    """Split on commas outside brackets and quotes, so ``[1, 2],[3, 4]`` gives two TOML arrays."""
    values: list[str] = []
    depth = 0
    quote = ""
    start = 0
    for i, char in enumerate(text):
        if quote:
            quote = "" if char == quote else quote
        elif char in "\"'":
            quote = char
        elif char in "[{":
            depth += 1
        elif char in "]}":
            depth -= 1
        elif char == "," and depth == 0:
            values.append(text[start:i].strip())
            start = i + 1
    values.append(text[start:].strip())
    return values


def parse_assignment_key(text: str, flag: str) -> tuple[str, str]:
    """``key=rest`` → (key, rest), refusing an empty key and the keys a campaign sets itself."""
    key, sep, rest = text.partition("=")
    key = key.strip()
    if not sep or not key or any(not part for part in key.split(".")):
        raise CampaignSyntaxError(f"{flag} {text!r}: expected KEY=VALUE, e.g. radio.loss=0.3")
    if key in RESERVED_KEYS:
        raise CampaignSyntaxError(f"{flag} {key}: set by the campaign, use --seeds")
    return key, rest.strip()


def parse_grid_axis(text: str) -> GridAxis:
    """``radio.loss=0,0.3`` → GridAxis; raises CampaignSyntaxError on a missing ``=`` or an empty value."""
    key, rest = parse_assignment_key(text, "--grid")
    values = _split_values(rest)
    if any(not v for v in values):
        raise CampaignSyntaxError(f"--grid {text!r}: empty value (expected KEY=V1,V2,...)")
    if len(set(values)) != len(values):
        raise CampaignSyntaxError(f"--grid {text!r}: a value is repeated")
    return GridAxis(key, tuple(values))


def check_axes(axes: Sequence[GridAxis], fixed: Sequence[str]) -> None:
    """A key may appear in one ``--grid`` only, and not also in ``--set``."""
    seen: set[str] = set()
    fixed_keys = {parse_assignment_key(item, "--set")[0] for item in fixed}
    for axis in axes:
        if axis.key in seen:
            raise CampaignSyntaxError(f"--grid {axis.key}: given twice")
        if axis.key in fixed_keys:
            raise CampaignSyntaxError(f"--grid {axis.key}: also given with --set")
        seen.add(axis.key)


def grid_cells(axes: Sequence[GridAxis]) -> list[tuple[tuple[str, str], ...]]:
    """Every combination of the axes' values (one empty cell without axes), first axis slowest."""
    return [tuple(zip((a.key for a in axes), values)) for values in itertools.product(*(a.values for a in axes))]


def expand(scenario: str, modes: Sequence[Mode], seeds: Sequence[int], axes: Sequence[GridAxis],
           fixed: Sequence[str] = ()) -> list[RunSpec]:
    """Every run of the campaign: grid cell x seed x mode, in the order they should be started."""
    runs = [RunSpec(scenario, mode, seed, cell, tuple(fixed))
            for cell in grid_cells(axes) for seed in seeds for mode in modes]
    if len(runs) > MAX_RUNS:
        raise CampaignSyntaxError(f"{len(runs)} runs: more than {MAX_RUNS}; narrow --seeds or --grid")
    return runs


def run_id(spec: RunSpec) -> str:
    """A 16-hex-digit id that depends only on what the run computes: scenario, mode, seed, sorted assignments.

    The assignments (grid cell and ``--set``) are sorted by key, so the flags' order does not matter.
    """
    assignments = sorted([*(f"{k}={v}" for k, v in spec.cell), *spec.fixed])
    canonical = json.dumps([spec.scenario, spec.mode.value, spec.seed, assignments], separators=(",", ":"))
    return hashlib.sha256(canonical.encode("utf-8")).hexdigest()[:16]
