"""Demonstrations -> skill bundle: fit the DSs, build the dataset, learn, compile, save.

The learning, the compiled table and the bundle are the babbling path's: the one pipeline
:func:`a2l.skills.pipeline.learn_bundle` (hill-climbing with the K2 score, the edge
``effect -> move`` fixed as in :func:`a2l.framework.loop.generate_skill`, the compiled
table, the bundle); only the rows differ (:mod:`a2l.lfd.dataset`). The bundle also carries
the DS of each behaviour (fitted to the time-aligned mean of its demonstrations), so the
executor can run the DS alone.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from a2l.lfd.config import DEFAULT, LfDConfig
from a2l.lfd.dataset import skill_discretizer, vector_field_rows
from a2l.lfd.demonstration import Demonstration
from a2l.lfd.ds import DiffeoDS
from a2l.skills.ds_bundle import DSArrays
from a2l.skills.phases import DSPhase

__all__ = ["Behaviour", "LearnedSkill", "fit_fields", "learn_skill"]


@dataclass
class Behaviour:
    """Demonstrations of one effect under one set of high-level states.

    Attributes
    ----------
    demos : list of Demonstration
        In the object frame, 3-D, ending at the object (the origin).
    effect : str
        The effect they produce (a value of the skill's effect variable).
    states : dict of str to str
        High-level states they were given under (``{}``: any).
    rows : callable, optional
        Builds the behaviour's raw rows instead of
        :func:`a2l.lfd.dataset.vector_field_rows` (same arguments: fields, demos, effect,
        cfg, states, first episode id), e.g. with actions (:mod:`a2l.lfd.manipulation_skills`).
    phase : str
        Non-empty: the behaviour is also a DS phase of the bundle (:mod:`a2l.skills.phases`:
        its mean DS, applying under `states`), run by ``run_skill(mode="ds")``.
    end_action : str or None
        The phase's action within `tolerance` of its target (``"close"``, ``"stay"``).
    tolerance : float
        The phase's target tolerance (m).
    """

    demos: list[Demonstration]
    effect: str
    states: dict[str, str] = field(default_factory=dict)
    rows: Callable[..., pd.DataFrame] | None = None
    phase: str = ""
    end_action: str | None = None
    tolerance: float = 0.01


@dataclass
class LearnedSkill:
    """What :func:`learn_skill` made.

    Attributes
    ----------
    name : str
    bundle : Path
        The skill bundle (table + DS).
    table : a2l.skills.PolicyTable
        The compiled table the bundle holds.
    ds : list of DiffeoDS
        The DS of each behaviour (mean of its demonstrations), in behaviour order.
    rows : int
        Rows of the discrete dataset the network was learned from.
    timings : dict of str to float
        Seconds spent fitting the DSs (``fit``), building the dataset (``dataset``),
        learning (``learn``), compiling (``compile``) and saving (``save``).
    """

    name: str
    bundle: Path
    table: Any
    ds: list[DiffeoDS]
    rows: int
    timings: dict[str, float]


def fit_fields(demos: Sequence[Demonstration], cfg: LfDConfig = DEFAULT) -> list[DiffeoDS]:
    """One diffeomorphic DS per demonstration (``cfg.maps`` maps each)."""
    return [DiffeoDS.fit(d, K=cfg.maps) for d in demos]


def learn_skill(name: str, behaviours: Sequence[Behaviour], path: str | os.PathLike[str],
                cfg: LfDConfig = DEFAULT, high_level: Sequence[Any] = (),
                planar: bool = True, n_effects: int = 4,
                discretizer: Any | None = None, context_edges: bool = False,
                scene: dict[str, Any] | None = None,
                robot: dict[str, str] | None = None) -> LearnedSkill:
    """Learn a skill from demonstrated behaviours and save its bundle (atomically).

    Parameters
    ----------
    name : str
        The skill's name (in the bundle).
    behaviours : sequence of Behaviour
        Each one's rows come from the DSs of its demonstrations, with its effect and states.
    path : str or PathLike
        The bundle file to write.
    cfg : LfDConfig
        Grid, discretization, DS and step-cap parameters.
    high_level : sequence of a2l.skills.HighLevelState
        High-level states of the table (every state the behaviours name must be one).
    planar : bool
        8 planar movements (push) or 26 in 3-D.
    n_effects : {4, 8}
        Push effects of the effect variable.
    discretizer : a2l.skills.Discretizer, optional
        Use this one instead of :func:`a2l.lfd.dataset.skill_discretizer` (a repertoire
        with actions, an effect variable holding ``grasped``...).
    context_edges : bool
        Fix every evidence variable as a parent of the movement (not only the effect):
        hill-climbing keeps the other edges it finds.
    scene : dict, optional
        The scene settings the skill was demonstrated and is meant to run with (e.g. the
        sideways pushes' ``{"gripper_yaw": 90.0}``), kept in the bundle's ``extra`` as
        ``lfd.scene``; ``a2l skill run`` applies them unless told otherwise.
    robot : dict, optional
        The robot the skill is learned for, as the bundle records it
        (:func:`a2l.lfd.library.robot_record`); None: none (it runs on any arm).

    Returns
    -------
    LearnedSkill

    Raises
    ------
    ValueError
        No behaviour, a behaviour without demonstrations, a state the table does not have,
        or a dataset with no usable row.
    """
    # imported here: the pipeline loads pgmpy (seconds), which the demonstrators, the
    # executor and the CLI's argument checks importing this module do not need
    from a2l.skills.pipeline import learn_bundle

    if not behaviours:
        raise ValueError(f"skill {name!r}: no behaviour to learn from")
    disc = discretizer or skill_discretizer(cfg, high_level, planar, n_effects)
    known = {h.name for h in disc.high_level}
    timings = dict.fromkeys(("fit", "dataset", "learn", "compile", "save"), 0.0)
    frames, means = [], []
    episode = 0
    for k, b in enumerate(behaviours):
        if not b.demos:
            raise ValueError(f"skill {name!r}: behaviour {k} ({b.effect}) has no demonstration")
        extra = sorted(set(b.states) - known)
        if extra:
            raise ValueError(f"skill {name!r}: behaviour {k} names state(s) {extra} that are "
                             f"not high-level states of the table ({sorted(known)})")
        t0 = time.perf_counter()
        fields_ = fit_fields(b.demos, cfg)
        means.append(DiffeoDS.fit(list(b.demos), K=cfg.maps))
        t1 = time.perf_counter()
        rows = (b.rows or vector_field_rows)(fields_, b.demos, b.effect, cfg, b.states,
                                             episode)
        # a state the behaviour does not constrain: its rows hold for every value
        for h in disc.high_level:
            if h.name not in b.states:
                rows = pd.concat([rows.assign(**{h.name: v}) for v in h.values],
                                 ignore_index=True)
        frames.append(rows)
        episode += len(rows)
        timings["fit"] += t1 - t0
        timings["dataset"] += time.perf_counter() - t1
    first = means[0]
    phases = [DSPhase(b.phase, means[k], dict(b.states), b.end_action, b.tolerance)
              for k, b in enumerate(behaviours) if b.phase]
    learned = learn_bundle(
        pd.concat(frames, ignore_index=True), disc, path, name=name, structure="hc-k2",
        constraints={"fixed_parents": list(disc.evidence if context_edges
                                           else [disc.effects.name])},
        robot=robot, step_cap=cfg.step_cap, smoothing=cfg.smoothing,
        extra=lambda rows: {"lfd": {
            "config": cfg.to_json(),
            "scene": dict(scene or {}),
            "behaviours": [{"effect": b.effect, "states": dict(b.states),
                            "n_demonstrations": len(b.demos)} for b in behaviours],
            "rows": rows}},
        ds=DSArrays(first.target, first.centers, first.vectors, first.rhos, first.speed,
                    first.direction),
        ds_phases=phases)
    timings["dataset"] += learned.timings["discretize"]
    for key in ("learn", "compile", "save"):
        timings[key] = learned.timings[key]
    return LearnedSkill(name, learned.path, learned.table, means, learned.rows, timings)
