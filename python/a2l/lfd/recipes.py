"""The registry of demonstrated skills: :class:`SkillRecipe` (how a skill is demonstrated,
learned and tried) and :data:`SKILLS`, filled by :mod:`a2l.lfd.library` with the push skills
and those of :mod:`a2l.lfd.manipulation_skills`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from a2l.lfd.config import LfDConfig
from a2l.lfd.skill import Behaviour

__all__ = ["SKILLS", "SkillRecipe", "get_recipe", "register_skill"]


@dataclass(frozen=True)
class SkillRecipe:
    """How a demonstrated skill is made and tried.

    Attributes
    ----------
    name : str
        Skill name (``"push_right"``).
    scene : str
        The :func:`a2l.sim.make_scene` scene it acts in (on any robot the scene takes).
    effect : str
        The effect it produces (the wanted effect of its runs).
    object_name : str
        The object it acts on.
    behaviours : callable ``(cfg, seed) -> list of Behaviour``
        The seeded scripted demonstrations.
    start : callable ``(rng) -> ndarray (3,)``
        A trial's end-effector start relative to the object.
    high_level : tuple of a2l.skills.HighLevelState
        High-level states of the table.
    planar : bool
        8 planar movements or 26 in 3-D.
    object_jitter : float
        A trial places the object within ± this of its home on each table axis (m).
    setup : callable ``(scene, rng) -> None``, optional
        Extra trial set-up after the reset (a high-level state to set...).
    discretizer : callable ``cfg -> a2l.skills.Discretizer``, optional
        Instead of :func:`a2l.lfd.dataset.skill_discretizer`.
    description : str
        One line for humans.
    config : LfDConfig, optional
        The skill's own configuration, used when the caller gives none (default:
        :data:`a2l.lfd.config.DEFAULT`): see :func:`skill_config`.
    context_edges : bool
        Learn with every context variable a fixed parent of the movement
        (:func:`a2l.lfd.skill.learn_skill`).
    scene_config : dict
        Scene config fields the skill is demonstrated and run with (e.g. the gripper's
        turn, ``{"gripper_yaw": 90.0}``), applied by
        :func:`a2l.lfd.library.make_skill_scene` to every scene whose config has them.
    """

    name: str
    scene: str
    effect: str
    object_name: str
    behaviours: Callable[[LfDConfig, int], list[Behaviour]]
    start: Callable[[np.random.Generator], np.ndarray]
    high_level: tuple[Any, ...] = ()
    planar: bool = True
    object_jitter: float = 0.02
    setup: Callable[[Any, np.random.Generator], None] | None = None
    discretizer: Callable[[LfDConfig], Any] | None = None
    description: str = ""
    extra: dict[str, Any] = field(default_factory=dict)
    config: LfDConfig | None = None
    context_edges: bool = False
    scene_config: dict[str, Any] = field(default_factory=dict)


#: Skill name -> recipe.
SKILLS: dict[str, SkillRecipe] = {}


def register_skill(recipe: SkillRecipe) -> None:
    """Add (or replace) a recipe in :data:`SKILLS`."""
    SKILLS[recipe.name] = recipe


def get_recipe(name: str) -> SkillRecipe:
    """The recipe of skill `name` (ValueError naming the known skills if there is none)."""
    if name not in SKILLS:
        raise ValueError(f"unknown skill {name!r}; known: {sorted(SKILLS)}")
    return SKILLS[name]
