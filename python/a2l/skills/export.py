"""From a compiled policy table to a :class:`~a2l.skills.spec.SkillSpec` (what
:func:`a2l.skills.save_bundle` writes)."""

from __future__ import annotations

from typing import Any

import numpy as np

from a2l import _core
from a2l.skills.compile import PolicyTable
from a2l.skills.discretizer import Discretizer
from a2l.skills.spec import SkillSpec, VariableSpec

__all__ = ["make_skill_spec"]


def make_skill_spec(
    table: PolicyTable,
    discretizer: Discretizer,
    *,
    name: str,
    robot: dict[str, str] | None = None,
    step_cap: int = 12,
    smoothing: bool = False,
    fallback: str = "none",
    clearance: float = 0.0,
    clearance_ratio: float = _core.CLEARANCE_RATIO,
    align: float = 0.0,
    avoid_revisits: bool = False,
    extra: dict[str, Any] | None = None,
) -> SkillSpec:
    """Build the bundle content of a skill from its compiled table.

    Each axis of the table becomes a bundle variable described by `discretizer` (its
    kind, bins or value names); the table's target states must be movement labels of
    ``discretizer.movements``, and give the repertoire's order in the bundle (directions in
    table order, then the actions).

    Parameters
    ----------
    table : PolicyTable
        Compiled by :func:`~a2l.skills.compile_policy`; its target is the movement.
    discretizer : Discretizer
        The discretization the network was learned with.
    name : str
        Skill name (``"push"``).
    robot : dict or None
        ``{"name", "urdf_sha256", "base_link", "tip_link"}``, or None (virtual scene).
    step_cap : int
        Most movements per run.
    smoothing : bool
        Neighbour smoothing (``docs/method.md``) in the runtime.
    fallback : {"none", "nearest", "approach"}
        The runtime's answer in a cell with no data (:class:`SkillSpec`).
    clearance : float
        The step's clearance rule (m; 0: off, :class:`SkillSpec`).
    clearance_ratio : float
        The clearance rule's bar (:class:`SkillSpec`).
    align : float
        The step's alignment rule (m; 0: off, :class:`SkillSpec`).
    avoid_revisits : bool
        The step's revisit rule (:class:`SkillSpec`).
    extra : dict, optional
        Free-form metadata; the discretizer's description is added under ``"discretizer"``.

    Returns
    -------
    SkillSpec
        With ``posterior`` of shape ``(*bins, n_moves)``, float64, C-contiguous, and ``argmax``
        of shape ``(*bins,)``, int32.

    Raises
    ------
    ValueError
        A table variable unknown to the discretizer, states that are not the discretizer's
        (in order), or a target state that is not a movement label.
    """
    if table.target != discretizer.movements.name:
        raise ValueError(
            f"table target {table.target!r} is not the movement variable "
            f"{discretizer.movements.name!r}"
        )
    specs = discretizer.variable_specs()
    expected = discretizer.state_names()
    variables: list[VariableSpec] = []
    for v in table.variables:
        if v not in specs:
            raise ValueError(
                f"table variable {v!r} is not a variable of the discretizer ({sorted(specs)})"
            )
        if list(table.states[v]) != list(expected[v]):
            raise ValueError(
                f"variable {v!r}: table states {table.states[v]} differ from the "
                f"discretizer's {expected[v]}; learn with the discretizer's state names"
            )
        variables.append(specs[v])
    moves = discretizer.movements
    pos = {label: i for i, label in enumerate(moves.labels)}
    unknown = [s for s in table.target_states if s not in pos]
    if unknown:
        raise ValueError(f"target state(s) {unknown} are not movement labels {moves.labels}")
    # the bundle's movement axis: directions first, then actions (docs/bundle_format.md)
    states = list(table.target_states)
    perm = [i for i, s in enumerate(states) if not moves.is_action(pos[s])]
    perm += [i for i, s in enumerate(states) if moves.is_action(pos[s])]
    n_dirs = sum(1 for s in states if not moves.is_action(pos[s]))
    new_index = np.empty(len(perm), dtype=np.int32)
    new_index[perm] = np.arange(len(perm), dtype=np.int32)
    argmax = np.asarray(table.argmax_indices)
    argmax = np.where(argmax < 0, -1, new_index[np.maximum(argmax, 0)])
    order = [pos[states[i]] for i in perm]
    meta = dict(extra or {})
    meta.setdefault("discretizer", discretizer.to_json())
    if table.ignored:
        meta.setdefault("ignored_evidence", list(table.ignored))
    return SkillSpec(
        name=name,
        variables=variables,
        directions=np.ascontiguousarray(moves.directions[order[:n_dirs]], dtype=np.int64),
        posterior=np.ascontiguousarray(table.values[..., perm], dtype=np.float64),
        argmax=np.ascontiguousarray(argmax, dtype=np.int32),
        step=moves.step,
        labels=[states[i] for i in perm[:n_dirs]],
        actions=[states[i] for i in perm[n_dirs:]],
        step_cap=step_cap,
        smoothing=smoothing,
        fallback=fallback,
        clearance=clearance,
        clearance_ratio=clearance_ratio,
        align=align,
        avoid_revisits=avoid_revisits,
        uniform_tolerance=table.uniform_tolerance,
        robot=robot,
        extra=meta,
    )
