"""The learn -> compile -> bundle pipeline: from raw interaction rows to a skill bundle.

One function, :func:`learn_bundle`, used by the framework's loop
(:func:`a2l.framework.loop.generate_skill`: babbled rows) and by learning from demonstration
(:func:`a2l.lfd.skill.learn_skill`: rows of the demonstrations' vector fields, plus their
DSs)::

    dataset --discretize--> discrete rows --learn_network--> Bayesian network
            --compile_policy--> policy table --make_skill_spec--> SkillSpec --save_bundle--> file

The callers differ only in where the rows come from, which edges they fix and what metadata
the bundle keeps.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from a2l import _core
from a2l.skills.bundle import save_bundle
from a2l.skills.compile import PolicyTable, compile_policy
from a2l.skills.discretizer import Discretizer
from a2l.skills.ds_bundle import DSArrays
from a2l.skills.export import make_skill_spec
from a2l.skills.learning import learn_network
from a2l.skills.phases import DSPhase
from a2l.skills.spec import SkillSpec

__all__ = ["LearnedBundle", "learn_bundle"]

#: The bundle's ``extra`` metadata, or a function of the number of usable rows giving it.
Extra = Mapping[str, Any] | Callable[[int], Mapping[str, Any]]


@dataclass(frozen=True)
class LearnedBundle:
    """What :func:`learn_bundle` made.

    Attributes
    ----------
    path : Path
        The written bundle.
    table : a2l.skills.PolicyTable
        The compiled table (the bundle holds the same numbers).
    spec : a2l.skills.SkillSpec
        The bundle's content (``posterior`` of shape ``(*bins, n_moves)``).
    rows : int
        Rows of the discrete dataset the network was learned from.
    timings : dict of str to float
        Seconds spent discretizing (``discretize``), learning the network (``learn``),
        compiling the table (``compile``) and building and writing the bundle (``save``).
    """

    path: Path
    table: PolicyTable
    spec: SkillSpec
    rows: int
    timings: dict[str, float]


def learn_bundle(
    dataset: pd.DataFrame,
    discretizer: Discretizer,
    path: str | os.PathLike[str],
    *,
    name: str,
    structure: str = "hc-k2",
    constraints: Mapping[str, Any] | None = None,
    robot: dict[str, str] | None = None,
    step_cap: int = 12,
    smoothing: bool = False,
    fallback: str = "none",
    clearance: float = 0.0,
    clearance_ratio: float = _core.CLEARANCE_RATIO,
    align: float = 0.0,
    avoid_revisits: bool = False,
    extra: Extra | None = None,
    ds: DSArrays | None = None,
    ds_phases: Sequence[DSPhase] | None = None,
) -> LearnedBundle:
    """Discretize `dataset`, learn the network, compile its table, write the skill bundle.

    Parameters
    ----------
    dataset : pandas.DataFrame, shape (n_rows, n_columns)
        Raw rows (positions, movements, effect, high-level states) as
        :meth:`a2l.skills.Discretizer.discretize` reads them.
    discretizer : a2l.skills.Discretizer
        The bins, effects and movement repertoire; the table's target is its movement
        variable and its evidence every other variable.
    path : str or PathLike
        The bundle file to write (atomically).
    name : str
        The skill's name (in the bundle and in error messages).
    structure : {"hc-k2", "hand-coded"}
        Structure learning (:func:`a2l.skills.learn_network`).
    constraints : mapping, optional
        Keyword arguments of :func:`a2l.skills.learn_structure` (edges to fix...), for
        ``"hc-k2"``.
    robot : dict or None
        The bundle's robot entry (None: virtual scene).
    step_cap : int
        Most movements per run.
    smoothing : bool
        The runtime's neighbour smoothing.
    fallback : {"none", "nearest", "approach"}
        The runtime's answer in a context cell with no data (:class:`SkillSpec`).
    clearance : float
        The step's clearance rule (m; 0: off, :class:`SkillSpec`).
    clearance_ratio : float
        The clearance rule's bar (:class:`SkillSpec`).
    align : float
        The step's alignment rule (m; 0: off, :class:`SkillSpec`).
    avoid_revisits : bool
        The step's revisit rule (:class:`SkillSpec`).
    extra : mapping or callable, optional
        The bundle's ``extra`` metadata, or ``extra(rows)`` giving it from the number of
        usable rows (the discretizer's description is added).
    ds : DSArrays, optional
        A DS stored beside the table (section ``ds``).
    ds_phases : sequence of DSPhase, optional
        DS phases stored beside the table (section ``ds_phases``).

    Returns
    -------
    LearnedBundle

    Raises
    ------
    ValueError
        No row survives the discretization, or a constraint the learning refuses.
    a2l.BundleError
        The result does not make a valid bundle (nothing is written).
    """
    t0 = time.perf_counter()
    discrete = discretizer.discretize(dataset)
    if len(discrete) == 0:
        raise ValueError(f"skill {name!r}: the dataset has no usable row")
    t1 = time.perf_counter()
    network = learn_network(discrete, structure=structure,
                            target=discretizer.movements.name,
                            state_names=discretizer.state_names(), **dict(constraints or {}))
    t2 = time.perf_counter()
    table = compile_policy(network, target=discretizer.movements.name,
                           evidence=discretizer.evidence)
    t3 = time.perf_counter()
    meta = extra(len(discrete)) if callable(extra) else extra
    spec = make_skill_spec(table, discretizer, name=name, robot=robot, step_cap=step_cap,
                           smoothing=smoothing, fallback=fallback, clearance=clearance,
                           clearance_ratio=clearance_ratio, align=align,
                           avoid_revisits=avoid_revisits,
                           extra=dict(meta) if meta is not None else None)
    out = save_bundle(spec, path, ds_phases=ds_phases or None, ds=ds)
    timings = {"discretize": t1 - t0, "learn": t2 - t1, "compile": t3 - t2,
               "save": time.perf_counter() - t3}
    return LearnedBundle(Path(out), table, spec, len(discrete), timings)
