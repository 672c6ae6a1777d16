"""DS phases of a skill: diffeomorphic DSs in the object's frame, each applying under some
high-level state values, with an action to emit at its target (``docs/bundle_format.md``,
section ``ds_phases``). The C++ ``step_ds`` runs them (:class:`a2l.skills.CppSkillRunner`
with ``mode="ds"``).

A phase's DS is 3-D and relative to the object: its input is ``x = eef - object`` and its
target is the wanted end-effector position relative to the object. The first phase whose
``when`` holds applies; within ``tolerance`` of its target it emits ``end_action`` (once per
run), then (or without an end action) the run has converged.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from a2l import _core
from a2l.errors import BundleError
from a2l.skills.bundle_format import read_bundle
from a2l.skills.ds_bundle import DSArrays
from a2l.skills.spec import ACTIONS, SkillSpec

__all__ = ["GRIPPER_VALUES", "DSPhase", "ds_phases_section", "load_ds_phases"]

#: Values of the high-level state ``gripper``.
GRIPPER_VALUES = ("open", "closed")


@dataclass(frozen=True)
class DSPhase:
    """One DS phase of a skill.

    Attributes
    ----------
    name : str
        Phase name (traces).
    ds : a2l.lfd.DiffeoDS or a2l._core.DiffeoDS
        3-D DS expressed relative to the object (x = eef - object; its target relative to the
        object). Anything with ``target`` (3,), ``centers`` and ``vectors`` (K, 3), ``rhos``
        (K,) and ``speed`` (and optionally ``direction``, default ``"to_demo"``) will do (e.g.
        :class:`a2l.skills.ds_bundle.DSArrays`).
    when : dict of str to str
        High-level state values the phase applies under; ``{}`` = always.
    end_action : str or None
        Action emitted once within `tolerance` of the target (one of ``ACTIONS``).
    tolerance : float
        Distance to the target within which it is reached (m), > 0.
    """

    name: str
    ds: Any
    when: dict[str, str] = field(default_factory=dict)
    end_action: str | None = None
    tolerance: float = 0.01


def _state_values(
    phases: Sequence[DSPhase], spec: SkillSpec, states: Mapping[str, Sequence[str]] | None
) -> dict[str, list[str]]:
    """Values of every state the phases name: `states`, else the table's high-level
    variable of that name, else the gripper's."""
    table = {v.name: list(v.values) for v in spec.variables if v.kind == "high_level"}
    out: dict[str, list[str]] = {}
    for i, p in enumerate(phases):
        for name in p.when:
            if name in out:
                continue
            if states is not None and name in states:
                out[name] = [str(v) for v in states[name]]
            elif name in table:
                out[name] = table[name]
            elif name == "gripper":
                out[name] = list(GRIPPER_VALUES)
            else:
                raise BundleError(
                    f"ds_phases.phases[{i}].when.{name}: the values of state '{name}' are "
                    "unknown (not a high-level variable of the table): pass them in ds_states"
                )
    return out


def ds_phases_section(
    phases: Sequence[DSPhase],
    spec: SkillSpec,
    states: Mapping[str, Sequence[str]] | None = None,
) -> tuple[dict[str, Any], list[tuple[str, np.ndarray]]]:
    """The manifest's ``ds_phases`` entry and the arrays (name, float64 array) it needs.

    Parameters
    ----------
    phases : sequence of DSPhase
        In priority order (the first whose ``when`` holds applies), 1 to 64.
    spec : SkillSpec
        The skill: a state's values are those of its high-level variable of the same name.
    states : mapping of str to sequence of str, optional
        Values of states the table does not hold (``gripper`` defaults to
        :data:`GRIPPER_VALUES`).

    Returns
    -------
    entry : dict
        ``{"states": [{name, values}], "phases": [{name, when, end_action, tolerance, ds}]}``.
    arrays : list of (str, ndarray)
        ``ds_phase<i>_centers`` (K, 3), ``ds_phase<i>_vectors`` (K, 3), ``ds_phase<i>_rhos``
        (K,) per phase.

    Raises
    ------
    a2l.BundleError
        A phase that is not a DSPhase, an unknown end action, a state whose values are
        unknown, or DS arrays of the wrong shapes (the C++ loader checks the rest, naming the
        phase and the field).
    """
    values = _state_values(phases, spec, states)
    entries, arrays = [], []
    for i, p in enumerate(phases):
        where = f"ds_phases.phases[{i}]"
        if not isinstance(p, DSPhase):
            raise BundleError(f"{where}: must be an a2l.skills.phases.DSPhase, got {type(p)}")
        if p.end_action is not None and p.end_action not in ACTIONS:
            raise BundleError(f"{where}.end_action: unknown action {p.end_action!r} ({ACTIONS})")
        try:
            ds_entry, ds_arrays = DSArrays(
                p.ds.target, p.ds.centers, p.ds.vectors, p.ds.rhos, p.ds.speed,
                getattr(p.ds, "direction", "to_demo"),
            ).section()
        except BundleError as exc:
            raise BundleError(f"{where}.ds: {exc}") from exc
        except AttributeError as exc:
            raise BundleError(f"{where}.ds: not a DS ({exc})") from exc
        entries.append({
            "name": str(p.name),
            "when": {str(k): str(v) for k, v in p.when.items()},
            "end_action": p.end_action,
            "tolerance": float(p.tolerance),
            "ds": ds_entry,
        })
        arrays += [(f"ds_phase{i}_{n[3:]}", a) for n, a in ds_arrays]
    section = {"states": [{"name": k, "values": v} for k, v in values.items()],
               "phases": entries}
    return section, arrays


def load_ds_phases(path: str | os.PathLike[str]) -> list[DSPhase]:
    """Read the DS phases of a skill bundle (validated by the C++ loader).

    Each phase's DS is built from its manifest entry (target, speed and ``direction``) and
    its arrays, as the C++ loader builds it.

    Parameters
    ----------
    path : str or PathLike
        The bundle file.

    Returns
    -------
    list of DSPhase
        In priority order, each ``ds`` an :class:`a2l._core.DiffeoDS` (3-D; wrap it in
        :class:`a2l.lfd.DiffeoDS` for the fit's helpers); empty if the bundle has no
        ``ds_phases`` section.

    Raises
    ------
    a2l.BundleError
        Malformed or corrupted (the message names the phase and the field).
    a2l.A2LFileNotFoundError
        The file cannot be read.
    """
    view, _ = read_bundle(path, _core.load_bundle_from_memory)
    section = view.manifest.get("ds_phases")
    if section is None:
        return []
    out = []
    for i, p in enumerate(section["phases"]):
        entry = p["ds"]
        ds = _core.DiffeoDS(np.asarray(entry["target"], dtype=np.float64),
                            view.array(f"ds_phase{i}_centers"), view.array(f"ds_phase{i}_vectors"),
                            view.array(f"ds_phase{i}_rhos"), float(entry["speed"]),
                            direction=str(entry["direction"]))
        out.append(DSPhase(p["name"], ds, dict(p["when"]), p["end_action"],
                           float(p["tolerance"])))
    return out
