"""Running a demonstrated skill in closed loop on a scene (:func:`run_skill`).

Every step reads the context (end-effector, object, high-level states), asks the skill for
the next movement and carries it out in the scene:

- ``mode="table"``: the context skill, through the C++ step (:class:`a2l.skills.CppSkillRunner`:
  bins -> compiled table -> movement; the same step ``a2l-run`` executes);
- ``mode="ds"``: the bundle's DS phases alone (:mod:`a2l.skills.phases`), through the C++
  ``step_ds``: at ``eef - object`` (the attractor follows the perceived object), a
  displacement of one movement's length along the DS velocity, capped at the distance to
  the target, or the phase's end action.

The run ends when the effect test says the effect is produced (or went wrong), when the
step returns a stop status (``step_cap``, ``unknown_context``...), when a movement cannot be
carried out for good (``unreachable``, ``workspace_limit``, ``joint_limit``) or at
``max_steps``. Effect tests (:mod:`a2l.rollout.effect_tests`, whose names are re-exported
here) are keyed by effect name: the pushes, ``grasped``, ``pressed`` and ``away`` are
registered there, other skills register theirs with :func:`register_effect_test`.

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

from a2l.errors import A2LValueError
from a2l.rollout.effect_tests import (
    EFFECT_TESTS,
    PUSH_DISTANCE,
    EffectTest,
    Progress,
    effect_test_of,
    light_test,
    push_test,
    register_effect_test,
    scene_test,
)

__all__ = ["EFFECT_TESTS", "PUSH_DISTANCE", "Progress", "SkillRun", "SkillStep", "push_test",
           "light_test", "register_effect_test", "run_skill", "scene_test"]

#: Movement statuses after which the run cannot go on (the same movement would be chosen).
_FATAL_MOVES = ("unreachable", "workspace_limit", "joint_limit")


@dataclass
class SkillStep:
    """One step of a run.

    Attributes
    ----------
    index : int
        Step number (0 first).
    status : str
        ``"ok"`` when a movement was chosen, else why the run stopped.
    label : str
        The movement's label (table mode), ``"ds"`` (DS mode) or ``""`` (none).
    displacement : ndarray, shape (3,)
        The commanded end-effector displacement (zero when none).
    move_status : str
        What the scene did with it (:class:`a2l.sim.MoveResult` status; ``""`` if none).
    eef, obj : ndarray, shape (3,)
        End-effector and object before the movement.
    states : dict of str to str
        High-level states the step saw.
    """

    index: int
    status: str
    label: str
    displacement: np.ndarray
    move_status: str
    eef: np.ndarray
    obj: np.ndarray
    states: dict[str, str]


@dataclass
class SkillRun:
    """A closed-loop run of a skill.

    Attributes
    ----------
    effect, mode : str
    steps : list of SkillStep
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
    steps: list[SkillStep] = field(default_factory=list)
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

    @property
    def trajectory(self) -> np.ndarray:
        """End-effector positions, shape (T, 3) (same as :attr:`eef`)."""
        return self.eef


class _TableStep:
    """The C++ step of a bundle's compiled table (:class:`a2l.skills.CppSkillRunner`,
    ``mode="table"``); an action (open, close, stay) is returned as its name, which
    :meth:`a2l.sim.Scene.execute` carries out."""

    def __init__(self, bundle: str) -> None:
        from a2l.skills import CppSkillRunner

        self.runner = CppSkillRunner(bundle, mode="table")
        self.skill = self.runner.skill
        self.step_len = self.runner.step_length
        self.cap = self.runner.step_cap
        self.directions = np.asarray(self.skill.movements.directions, dtype=int)

    def __call__(self, eef: np.ndarray, obj: np.ndarray, effect: str,
                 states: dict[str, str]) -> tuple[str, str, np.ndarray, Any]:
        try:
            out = self.runner.step(eef, obj, effect, states)
        except A2LValueError:  # a state value the table does not know
            return "unknown_context", "", np.zeros(3), None
        if out.status != "ok":
            return out.status, "", np.zeros(3), None
        if out.action is not None:  # open / close / stay: no displacement
            return "ok", out.action, np.zeros(3), out.action
        return "ok", out.label, np.asarray(out.displacement, dtype=float), \
            tuple(int(v) for v in self.directions[out.movement])


class _PhaseStep:
    """The bundle's DS phases (:mod:`a2l.skills.phases`) through the C++ ``step_ds``
    (:class:`a2l.skills.CppSkillRunner`, ``mode="ds"``): a DS displacement or the phase's
    end action (open / close / stay), the phase chosen by the high-level states."""

    def __init__(self, bundle: str) -> None:
        from a2l.skills import CppSkillRunner

        self.runner = CppSkillRunner(bundle, mode="ds")

    def __call__(self, eef: np.ndarray, obj: np.ndarray, effect: str,
                 states: dict[str, str]) -> tuple[str, str, np.ndarray, Any]:
        if not np.all(np.isfinite(obj)):
            return "unknown_context", "", np.zeros(3), None
        out = self.runner.step(eef, obj, effect, states)
        if out.status != "ok":
            return out.status, "", np.zeros(3), None
        if out.action is not None:
            return "ok", out.action, np.zeros(3), out.action
        disp = np.asarray(out.displacement, dtype=float)
        return "ok", f"ds:{out.phase}", disp, disp


def _observe(scene: Any, source: str | None) -> dict[str, Any]:
    src = source or getattr(scene.config, "context_source", "ground_truth")
    return scene.perceive() if src == "perceived" else scene.ground_truth()


def run_skill(scene: Any, bundle_path: str | os.PathLike[str], effect: str,
              mode: str = "table", max_steps: int | None = None,
              on_step: Callable[[int, SkillStep], None] | None = None,
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
    on_step : callable ``(k, SkillStep) -> None``, optional
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
        from the bundle's, or an unknown object.
    """
    t0 = time.perf_counter()
    if mode not in ("table", "ds"):
        raise ValueError(f"mode must be 'table' or 'ds', got {mode!r}")
    test = effect_test or effect_test_of(effect)
    if test is None:
        raise ValueError(f"no effect test for effect {effect!r}; known: {sorted(EFFECT_TESTS)}")
    path = os.fspath(bundle_path)
    table = _TableStep(path)
    if abs(scene.step_length - table.step_len) > 1e-9:
        raise ValueError(f"the scene moves by {scene.step_length} m, the skill bundle "
                         f"'{path}' by {table.step_len} m: make the scene with step="
                         f"{table.step_len}")
    stepper: Any = table if mode == "table" else _PhaseStep(path)
    cap = table.cap if max_steps is None else int(max_steps)
    names = scene.object_names
    name = object_name or ("box" if "box" in names else scene.primary_object)
    if name not in names:
        raise ValueError(f"scene {scene.name!r} has no object {name!r}; it has {list(names)}")

    def look() -> tuple[np.ndarray, dict[str, str]]:
        obs = _observe(scene, source)
        pos = obs["objects"].get(name)
        obj = np.full(3, np.nan) if pos is None else np.asarray(pos, dtype=float)
        states = dict(states_fn(scene)) if states_fn else dict(obs["states"])
        return obj, states

    def truth() -> np.ndarray:
        return np.asarray(scene.ground_truth()["objects"][name], dtype=float)

    run = SkillRun(effect, mode)
    obj, states = look()
    start_obj, start_states = obj.copy(), dict(states)
    eefs, objs = [], []
    produced = np.zeros(3)
    k = 0
    while True:
        eef = np.asarray(scene.eef_position(), dtype=float)
        eefs.append(eef)
        objs.append(obj)
        pr = Progress(effect, produced.copy(), start_obj, obj, eef, start_states, states, scene)
        done, ok = test(pr)
        if done:
            run.success = ok
            run.stop = "effect_produced" if ok else "effect_failed"
            run.steps.append(SkillStep(k, run.stop, "", np.zeros(3), "", eef, obj, states))
            break
        if k >= cap:
            run.stop = "max_steps" if max_steps is not None else "step_cap"
            run.steps.append(SkillStep(k, run.stop, "", np.zeros(3), "", eef, obj, states))
            break
        status, label, disp, command = stepper(eef, obj, effect, states)
        if status != "ok":
            run.stop = status
            run.steps.append(SkillStep(k, status, "", np.zeros(3), "", eef, obj, states))
            break
        before = truth()
        if mode == "table" or isinstance(command, str):  # a direction or an action
            res = scene.execute(command)
        else:
            res = scene.execute_displacement(command)
        produced += truth() - before
        step = SkillStep(k, "ok", label, np.asarray(disp, float), res.status, eef, obj, states)
        run.steps.append(step)
        if res.status in _FATAL_MOVES:
            run.stop = res.status
            eef, (obj, states) = np.asarray(scene.eef_position(), dtype=float), look()
            eefs.append(eef)
            objs.append(obj)
            run.steps.append(SkillStep(k + 1, res.status, "", np.zeros(3), "", eef, obj,
                                       states))
            break
        if on_step is not None:
            on_step(k, step)
        k += 1
        obj, states = look()
    run.eef = np.asarray(eefs)
    run.obj = np.asarray(objs)
    run.produced = produced
    run.wall = time.perf_counter() - t0
    return run
