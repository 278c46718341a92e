"""Plan files: a plan (:mod:`mission_plan.plans`) as human-readable JSON, encoded and decoded with msgspec.

Decoding is strict: msgspec checks every type, the plans' ``__post_init__`` check their invariants, and an
unknown key anywhere (a typo in a hand-edited plan) is an error naming the closest known key, as in a scenario.
Every failure is one line, :class:`PlanFileError`, for the caller to print before exiting with 2.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypeVar

import msgspec
import msgspec.inspect as mi

from mission_plan.plans import PLAN_TAG_FIELD, AgentPlan, CamerasPlan, FleetPlan
from mission_plan.scenario_files import load_scenario
from mission_plan.scenario_schema import Scenario
from mission_plan.table_fields import ScenarioError
from mission_plan.unknown_keys import dotted, first_unknown, unknown_key_message

Plan = TypeVar("Plan", AgentPlan, FleetPlan, CamerasPlan)


class PlanFileError(ValueError):
    """A plan file that cannot be read or is not a valid plan of the expected kind; the message is one line."""


def encode_plan(plan: AgentPlan | FleetPlan | CamerasPlan) -> bytes:
    """The plan as indented JSON (one key a line, so a person can read and diff it)."""
    return msgspec.json.format(msgspec.json.encode(plan), indent=1) + b"\n"


def _unknown_key(value: Any, info: mi.Type, where: str) -> str | None:
    """The message for the first key of ``value`` the type ``info`` does not know, searching nested values."""
    if isinstance(info, (mi.StructType, mi.DataclassType)) and isinstance(value, dict):
        fields = {f.encode_name: f.type for f in info.fields}
        tag_field = getattr(info, "tag_field", None)
        known = set(fields) | ({tag_field} if tag_field else set())
        unknown = first_unknown(value, known)
        if unknown is not None:
            return unknown_key_message(where, unknown, known)
        found = (_unknown_key(value[name], sub, dotted(where, name)) for name, sub in fields.items() if name in value)
        return next((message for message in found if message is not None), None)
    if isinstance(info, (mi.ListType, mi.VarTupleType)) and isinstance(value, list):
        found = (_unknown_key(item, info.item_type, f"{where}[{i}]") for i, item in enumerate(value))
        return next((message for message in found if message is not None), None)
    if isinstance(info, mi.TupleType) and isinstance(value, list):
        found = (_unknown_key(item, sub, f"{where}[{i}]") for i, (item, sub) in enumerate(zip(value, info.item_types)))
        return next((message for message in found if message is not None), None)
    if isinstance(info, mi.DictType) and isinstance(value, dict):
        found = (_unknown_key(item, info.value_type, dotted(where, str(key))) for key, item in value.items())
        return next((message for message in found if message is not None), None)
    if isinstance(info, mi.UnionType):
        found = (_unknown_key(value, sub, where) for sub in info.types)
        return next((message for message in found if message is not None), None)
    return None


def decode_plan(data: bytes, plan_type: type[Plan]) -> Plan:
    """Decode and validate a plan of ``plan_type``; raises :class:`PlanFileError` with a one-line reason."""
    try:
        raw = msgspec.json.decode(data)
    except msgspec.DecodeError as exc:
        raise PlanFileError(f"not valid JSON ({exc})") from None
    info = mi.type_info(plan_type)
    assert isinstance(info, mi.StructType)
    if not isinstance(raw, dict) or PLAN_TAG_FIELD not in raw:
        raise PlanFileError(f"no {PLAN_TAG_FIELD!r} key: not a FloodWatch plan (expected {info.tag!r})")
    if raw[PLAN_TAG_FIELD] != info.tag:
        raise PlanFileError(f"holds plan {raw[PLAN_TAG_FIELD]!r}, expected {info.tag!r}")
    message = _unknown_key(raw, info, "")
    if message is not None:
        raise PlanFileError(message)
    try:
        return msgspec.json.decode(data, type=plan_type)
    except msgspec.ValidationError as exc:
        raise PlanFileError(" ".join(str(exc).split())) from None


def write_plan(path: Path, plan: AgentPlan | FleetPlan | CamerasPlan) -> Path:
    """Write ``plan`` to ``path`` (creating its folder); returns the path."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(encode_plan(plan))
    return path


def read_plan(path: Path, plan_type: type[Plan]) -> Plan:
    """Read a plan file; :class:`PlanFileError` names the file and the first problem on one line."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise PlanFileError(f"plan {path}: cannot read it ({exc.strerror or exc})") from None
    try:
        return decode_plan(data, plan_type)
    except PlanFileError as exc:
        raise PlanFileError(f"plan {path}: {exc}") from None


def plan_or_scenario(plan_path: Path | None, scenario: str | None, overrides: Sequence[str], plan_type: type[Plan],
                     slice_of: Callable[[Scenario], Plan]) -> Plan:
    """A process's plan: its ``--plan`` file, or ``--scenario`` (default circle, with ``--set``) resolved locally
    through this package and sliced by ``slice_of`` (a scenario whose pads are "auto" then fails: it needs the
    flood model, which only the ground station resolves)."""
    if plan_path is not None:
        if scenario is not None or overrides:
            raise ScenarioError("--plan: the plan is already resolved; --scenario and --set apply without it")
        return read_plan(plan_path, plan_type)
    return slice_of(load_scenario(scenario or "circle", overrides))
