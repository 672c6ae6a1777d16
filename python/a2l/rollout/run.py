"""Running a skill bundle in closed loop on a scene (:func:`run_skill`): a demonstrated
skill, a skill of the framework's loop, a plan step.

Every step reads the context (end-effector, object, high-level states), asks the skill for
the next movement and carries it out in the scene:

- ``mode="table"``: the context skill, through the C++ step
  (:class:`a2l.rollout.policy.TablePolicy`: bins -> compiled table -> movement; the same
  step ``a2l-run`` executes);
- ``mode="ds"``: the bundle's DS phases alone (:mod:`a2l.skills.phases`), through the C++
  ``step_ds`` (:class:`a2l.rollout.policy.PhasePolicy`): at ``eef - object`` (the
  attractor follows the perceived object), a displacement of one movement's length along
  the DS velocity, capped at the distance to the target, or the phase's end action.

The loop is :func:`a2l.rollout.loop.closed_loop`, the scene its
:class:`a2l.rollout.world.SceneWorld`.

The run ends when the effect test says the effect is produced (or went wrong), when the
step returns a stop status (``step_cap``, ``unknown_context``...), when a movement cannot be
carried out for good (``unreachable``, ``workspace_limit``, ``joint_limit``) or at
``max_steps``. Effect tests (:mod:`a2l.rollout.effect_tests`) are keyed by effect name: the
pushes, ``grasped``, ``pressed`` and ``away`` are registered there, other skills register
theirs with :func:`~a2l.rollout.effect_tests.register_effect_test`.

The displacement an effect test sees is the one the robot produced: the sum, over the
executed movements, of the object's displacement during each one, so a perturbation that
teleports the object between two steps (:meth:`a2l.sim.Scene.perturb`) is not counted.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from a2l.rollout.effect_tests import EFFECT_TESTS, EffectTest, Progress, effect_test_of
from a2l.rollout.loop import LoopStep, closed_loop
from a2l.rollout.policy import TablePolicy, skill_policy
from a2l.rollout.protocol import SceneProtocol
from a2l.rollout.world import SceneWorld

__all__ = ["SkillRun", "run_skill"]


@dataclass
class SkillRun:
    """A closed-loop run of a skill.

    Attributes
    ----------
    effect, mode : str
    steps : list of LoopStep
        Every step, the last one holding the stop status.
    eef, obj : ndarray, shape (T, 3)
        End-effector and object at each step (T = len(steps); the last row is where the
        run ended).
    success : bool
        The effect test's verdict.
    stop : str
        Why the run ended: ``effect_produced``, ``effect_failed`` (the test says done, not
        success), a step status (``step_cap``, ``unknown_context``, ``converged``), a
        movement status (``unreachable``...) or ``max_steps``.
    produced : ndarray, shape (3,)
        Object displacement the movements produced.
    wall : float
        Seconds.
    """

    effect: str
    mode: str
    steps: list[LoopStep] = field(default_factory=list)
    eef: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    obj: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    success: bool = False
    stop: str = ""
    produced: np.ndarray = field(default_factory=lambda: np.zeros(3))
    wall: float = 0.0

    @property
    def statuses(self) -> list[str]:
        """The status of every step."""
        return [s.status for s in self.steps]

    @property
    def movements(self) -> int:
        """Movements carried out (or attempted)."""
        return sum(1 for s in self.steps if s.status == "ok")


def run_skill(scene: SceneProtocol, bundle_path: str | os.PathLike[str], effect: str,
              mode: str = "table", max_steps: int | None = None,
              on_step: Callable[[int, LoopStep], None] | None = None,
              states_fn: Callable[[Any], dict[str, str]] | None = None,
              object_name: str | None = None, source: str | None = None,
              effect_test: EffectTest | None = None) -> SkillRun:
    """Run a skill bundle in closed loop on `scene` from where the scene is now.

    Parameters
    ----------
    scene : a2l.sim.Scene
        Reset and placed by the caller (e.g. :func:`a2l.lfd.library.reset_for_trial`); its
        movement length must be the bundle's.
    bundle_path : path
        The skill bundle (table + DS, :func:`a2l.lfd.skill.learn_skill`).
    effect : str
        The wanted effect (a value of the bundle's effect variable).
    mode : {"table", "ds"}
        The context skill or the DS alone.
    max_steps : int, optional
        Most steps (default: the bundle's step cap).
    on_step : callable ``(k, LoopStep) -> None``, optional
        Called after step k was carried out (a perturbation may be applied there).
    states_fn : callable ``scene -> dict``, optional
        The high-level states a step sees (default: the observed ones).
    object_name : str, optional
        The object the skill acts on (default: ``"box"`` when the scene has one, else the
        scene's primary object).
    source : {"perceived", "ground_truth"}, optional
        Where object positions and states come from (default: the scene's config).
    effect_test : callable, optional
        Default: ``EFFECT_TESTS[effect]``.

    Returns
    -------
    SkillRun

    Raises
    ------
    ValueError
        Unknown mode, no effect test for `effect`, a scene whose movement length differs
        from the bundle's, an unknown object, or a bundle learned for another robot than
        the scene's.
    """
    t0 = time.perf_counter()
    if mode not in ("table", "ds"):
        raise ValueError(f"mode must be 'table' or 'ds', got {mode!r}")
    test = effect_test or effect_test_of(effect)
    if test is None:
        raise ValueError(f"no effect test for effect {effect!r}; known: {sorted(EFFECT_TESTS)}")
    path = os.fspath(bundle_path)
    table = TablePolicy(path, effect)
    if abs(scene.step_length - table.step_length) > 1e-9:
        raise ValueError(f"the scene moves by {scene.step_length} m, the skill bundle "
                         f"'{path}' by {table.step_length} m: make the scene with step="
                         f"{table.step_length}")
    entry = getattr(scene, "robot_entry", None)
    if entry is not None:
        entry.check_learned_for(table.skill.robot, f"skill bundle '{path}'")
    policy = table if mode == "table" else skill_policy(path, effect, mode)
    cap = table.step_cap if max_steps is None else int(max_steps)
    names = scene.object_names
    name = object_name or ("box" if "box" in names else scene.primary_object)
    if name not in names:
        raise ValueError(f"scene {scene.name!r} has no object {name!r}; it has {list(names)}")
    world = SceneWorld(scene, name, source, states_fn, displacements=mode == "ds")
    start: list[Any] = []

    def effect_done(k: int, eef: np.ndarray, obj: np.ndarray, states: dict[str, str]
                    ) -> str | None:
        if not start:
            start.extend((obj.copy(), dict(states)))
        pr = Progress(effect, world.produced.copy(), start[0], obj, eef, start[1], states,
                      scene, true_obj=world.truth())
        done, ok = test(pr)
        if not done:
            return None
        return "effect_produced" if ok else "effect_failed"

    run = closed_loop(world, policy, effect_done, cap,
                      cap_status="max_steps" if max_steps is not None else "step_cap",
                      on_step=on_step)
    return SkillRun(effect, mode, run.steps, run.eef, run.obj,
                    run.stop == "effect_produced", run.stop, world.produced,
                    time.perf_counter() - t0)
