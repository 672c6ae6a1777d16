"""One trial of ``a2l experiment perturbations``: a skill run without perturbation, then
under each perturbation from the same start (:func:`trial_task`).

A perturbation (:class:`Perturbation`) is drawn from the trial's seed and the condition only
(:func:`draw_perturbation`) and applied between two steps of :func:`a2l.rollout.run.run_skill`
through :meth:`a2l.sim.Scene.perturb`; the record says what was measured of it (the object's
displacement, how long and how still the arm was held, the light before and after).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from a2l.lfd.config import LfDConfig
from a2l.robot import DEFAULT_ROBOT
from a2l.rollout.protocol import SceneProtocol

__all__ = ["CONDITIONS", "EFFECT_BY_LIGHT", "HOLD_RANGE", "LIT_SCENES", "MODES", "MOVE_RANGE",
           "WINDOW", "Perturbation", "PerturbationTrial", "draw_perturbation", "light_effects",
           "movement_seconds", "skill_scene", "skill_test", "trial_task"]

#: The perturbation conditions, in report order.
CONDITIONS = ("none", "move_object", "hold", "toggle_light")
#: Execution modes: the context skill (table) and the DS alone.
MODES = ("table", "ds")
#: A scene without a light -> the scene with the same object and a lamp.
LIT_SCENES = {"push": "press", "grasp": "grasp_light"}
#: Light value -> effect demonstrated under it, for skills whose table has the light
#: (unless the recipe's ``extra["effect_by_light"]`` says otherwise).
EFFECT_BY_LIGHT = {"off": "grasped", "on": "away"}
#: Mid-action: after a movement between these fractions of the unperturbed run.
WINDOW = (1 / 3, 2 / 3)
MOVE_RANGE = (0.03, 0.05)  # m
HOLD_RANGE = (1.0, 2.0)    # s

#: Two runs follow the same path when their end-effector positions agree within this (m).
#: Episode starts are bitwise the same whatever ran before (a2l.sim.bodies,
#: tests/python/test_sim_exact_start.py); the tolerance is a margin.
SAME_PATH = 1e-3

_PERTURB_STREAM = 0x70657274  # perturbation draws apart from the trial's start draws


@dataclass(frozen=True)
class Perturbation:
    """One perturbation drawn for a trial.

    Attributes
    ----------
    condition : str
        One of :data:`CONDITIONS`.
    after : int
        Applied after this many steps of the run (0: never; the unperturbed run was too
        short to have a middle).
    angle, distance : float
        ``move_object``: direction on the table (rad) and length (m).
    hold_steps : int
        ``hold``: commanded movements the arm does not carry out.
    hold_s : float
        ``hold``: their duration (``hold_steps`` movement times, s).
    """

    condition: str
    after: int = 0
    angle: float = 0.0
    distance: float = 0.0
    hold_steps: int = 0
    hold_s: float = 0.0


@dataclass(frozen=True)
class PerturbationTrial:
    """One trial of a skill under the perturbations, as a worker runs it
    (:func:`trial_task`).

    Attributes
    ----------
    skill : str
        The skill tried under every condition (:data:`a2l.lfd.library.SKILLS`).
    bundle : str
        The bundle it was learned into.
    mode : {"table", "ds"}
        The context skill (the compiled table) or the DS alone (:data:`MODES`).
    seed : int
        Trial seed: the start, and every perturbation's draw (:func:`draw_perturbation`).
    scene : str
        The scene the skill runs in (:func:`skill_scene`).
    conditions : tuple of str
        The conditions run, of :data:`CONDITIONS` (the unperturbed run comes first
        whether ``"none"`` is among them or not; it is reported only if it is).
    config : LfDConfig
        The skill's configuration.
    context_source : {"perceived", "ground_truth"}
        Where the skill reads the context: the camera (default) or the simulator's truth.
    robot : str
        The robot of the scene (a built-in name or a robot file).
    """

    skill: str
    bundle: str
    mode: str
    seed: int
    scene: str
    conditions: tuple[str, ...]
    config: LfDConfig
    context_source: str = "perceived"
    robot: str = DEFAULT_ROBOT


def draw_perturbation(condition: str, seed: int, movements: int,
                      movement_s: float) -> Perturbation:
    """The perturbation of `condition` for trial `seed` (every draw from the two only).

    Parameters
    ----------
    condition : str
        One of :data:`CONDITIONS`.
    seed : int
        Trial seed.
    movements : int
        Steps of the unperturbed run (its middle is where the perturbation goes).
    movement_s : float
        Duration of one movement (s); a hold lasts a whole number of them in
        :data:`HOLD_RANGE`.
    """
    if condition not in CONDITIONS:
        raise ValueError(f"unknown condition {condition!r}; known: {list(CONDITIONS)}")
    if condition == "none":
        return Perturbation(condition)
    rng = np.random.default_rng(np.random.SeedSequence(
        [int(seed), _PERTURB_STREAM, CONDITIONS.index(condition)]))
    u, angle, dist, dur = rng.random(), rng.uniform(0, 2 * np.pi), \
        rng.uniform(*MOVE_RANGE), rng.uniform(*HOLD_RANGE)
    after = 0
    if movements >= 2:
        lo = max(1, math.ceil(WINDOW[0] * movements))
        hi = min(movements - 1, max(lo, math.floor(WINDOW[1] * movements)))
        after = lo + min(int(u * (hi - lo + 1)), hi - lo)
    if condition == "move_object":
        return Perturbation(condition, after, angle=float(angle), distance=float(dist))
    if condition == "hold":
        lo_n = math.ceil(HOLD_RANGE[0] / movement_s - 1e-9)
        hi_n = max(lo_n, math.floor(HOLD_RANGE[1] / movement_s + 1e-9))
        n = int(min(max(round(dur / movement_s), lo_n), hi_n))
        return Perturbation(condition, after, hold_steps=n, hold_s=n * movement_s)
    return Perturbation(condition, after)


def skill_scene(recipe: Any) -> str:
    """The scene the skill is tried in: its own if it has a light, else a lit one."""
    return LIT_SCENES.get(recipe.scene, recipe.scene)


def movement_seconds(scene: SceneProtocol) -> float:
    """Simulated time of one movement (and of one held movement) in a Baxter scene (s)."""
    cfg = scene.config
    return max(1, round(cfg.step / cfg.speed / cfg.time_step)) * cfg.time_step


def light_effects(recipe: Any, cfg: LfDConfig) -> dict[str, str] | None:
    """Light value -> the effect demonstrated under it, for a skill whose table has the
    light (a high-level state of the recipe or of its discretizer); None for the others."""
    names = {getattr(h, "name", None) for h in recipe.high_level}
    if recipe.discretizer is not None:
        names |= {h.name for h in getattr(recipe.discretizer(cfg), "high_level", ())}
    if "light" not in names:
        return None
    return dict(recipe.extra.get("effect_by_light", EFFECT_BY_LIGHT))


def _effect_test(effect: str) -> Callable[[Any], tuple[bool, bool]]:
    """The test of a light-independent skill's effect, blind to the light."""
    from a2l.rollout.effect_tests import SCENE_OUTCOMES, effect_test_of, scene_outcome, scene_test

    if effect == "pressed":  # pressed by the robot: the toggle alone is no press
        def pressed(pr: Any) -> tuple[bool, bool]:
            ok = pr.scene.presses > 0
            return ok, ok
        return pressed
    if effect in SCENE_OUTCOMES:  # the scene's outcome, blind to the light
        return scene_test(scene_outcome(effect))
    test = effect_test_of(effect)
    if test is None:
        raise ValueError(f"no effect test for {effect!r}")
    return test


def skill_test(recipe: Any, by_light: dict[str, str] | None
               ) -> Callable[[Any], tuple[bool, bool]]:
    """The effect test of a trial: a light-independent skill's ignores the light; a
    light-dependent skill's is the test of ``by_light[light]`` for the light seen at each
    step (:func:`a2l.rollout.effect_tests.light_test`)."""
    from a2l.rollout.effect_tests import light_test

    if by_light is None:
        return _effect_test(recipe.effect)
    return light_test(by_light)


def _scene(skill: str, scene_name: str, cfg: LfDConfig, source: str = "perceived",
           robot: str = DEFAULT_ROBOT) -> Any:
    """A new scene for one trial task (closed by the caller). Not one scene per worker: a
    rollout's physics was not bitwise the same after different earlier trials in the same
    scene (1 and 2 workers once differed by 0.2 mm on one DS run, docs/experiments/
    perturbations.md), while a new scene makes a trial depend on its task alone."""
    from a2l.lfd.library import make_skill_scene

    return make_skill_scene(skill, 0, cfg, scene=scene_name, context_source=source,
                            robot=robot)


def _truth(scene: SceneProtocol, name: str) -> np.ndarray:
    return np.asarray(scene.ground_truth()["objects"][name], dtype=float)


def _perturbed_run(scene: SceneProtocol, task: PerturbationTrial, plan: Perturbation | None,
                   test: Callable[[Any], tuple[bool, bool]]) -> tuple[Any, dict[str, Any]]:
    """Reset for the trial and run the skill, applying `plan` after its step."""
    from a2l.lfd.library import SKILLS, reset_for_trial
    from a2l.rollout.run import run_skill

    recipe = SKILLS[task.skill]
    obj = recipe.object_name
    log: dict[str, Any] = {"applied": False}

    def on_step(k: int, _step: Any) -> None:
        if plan is None or log["applied"] or k + 1 != plan.after:
            return
        log.update(applied=True, eef_at=scene.eef_position().tolist(),
                   object_before=_truth(scene, obj).tolist(),
                   light_before=scene.ground_truth()["states"].get("light", ""))
        if plan.condition == "move_object":
            # the drawn direction, else the next quarter turns (the table's edge)
            for turn in range(4):
                a = plan.angle + turn * np.pi / 2
                delta = plan.distance * np.array([np.cos(a), np.sin(a)])
                try:
                    scene.perturb("move_object", name=obj, delta=tuple(delta))
                except ValueError:
                    continue
                log["delta"] = delta.tolist()
                break
        elif plan.condition == "hold":
            scene.perturb("hold", steps=plan.hold_steps)
        elif plan.condition == "toggle_light":
            scene.perturb("toggle", state="light")
        log.update(object_after=_truth(scene, obj).tolist(),
                   light_after=scene.ground_truth()["states"].get("light", ""))

    reset_for_trial(scene, task.skill, task.seed)
    run = run_skill(scene, task.bundle, recipe.effect, mode=task.mode,
                    on_step=on_step, effect_test=test, object_name=obj)
    return run, log


def _record(task: PerturbationTrial, run: Any, plan: Perturbation, log: dict[str, Any],
            base: Any, movement_s: float, recipe: Any,
            by_light: dict[str, str] | None) -> dict[str, Any]:
    """One row of ``trials.csv`` (plus the trajectories, kept apart)."""
    after = plan.after if log["applied"] else 0
    row: dict[str, Any] = {
        "skill": task.skill, "mode": task.mode, "condition": plan.condition,
        "seed": task.seed, "success": bool(run.success), "stop": run.stop,
        "movements": int(run.movements), "steps": len(run.steps) - 1,
        "applied": bool(log["applied"]), "after": after,
        "displacement_m": np.nan, "hold_s": np.nan, "hold_planned_s": np.nan,
        "held_observed": 0,
        "hold_drift_m": np.nan, "light_before": log.get("light_before", ""),
        "light_after": log.get("light_after", ""),
        "prefix_identical": True, "same_as_none": True, "expected_effect": recipe.effect,
        "light_dependent": by_light is not None,
    }
    if plan.condition != "none":
        n = min(after + 1, len(base.eef), len(run.eef)) if after else 0
        row["prefix_identical"] = bool(np.allclose(run.eef[:n], base.eef[:n], rtol=0,
                                                   atol=SAME_PATH))
        row["same_as_none"] = bool(run.eef.shape == base.eef.shape
                                   and np.allclose(run.eef, base.eef, rtol=0, atol=SAME_PATH)
                                   and run.success == base.success)
    if log["applied"] and plan.condition == "move_object":
        row["displacement_m"] = float(np.linalg.norm(
            np.subtract(log["object_after"], log["object_before"])))
    if log["applied"] and plan.condition == "hold":
        held = [s.index for s in run.steps if s.move_status == "held"]
        row["held_observed"] = len(held)
        row["hold_s"] = len(held) * movement_s
        row["hold_planned_s"] = plan.hold_s
        rows = run.eef[after:after + len(held) + 1]
        row["hold_drift_m"] = float(np.max(np.linalg.norm(rows - rows[0], axis=1)))
    if by_light is not None:
        light = row["light_after"] or run.steps[0].states.get("light", "off")
        row["expected_effect"] = by_light.get(light, recipe.effect)
    row["eef"], row["obj"] = run.eef, run.obj
    return row


def trial_task(task: PerturbationTrial) -> list[dict[str, Any]]:
    """One trial: the skill runs without perturbation, then under each other condition of
    ``task.conditions`` from the same start; returns one record per condition (``none``
    first).
    """
    from a2l.lfd.library import SKILLS

    cfg = task.config
    recipe = SKILLS[task.skill]
    by_light = light_effects(recipe, cfg)
    test = skill_test(recipe, by_light)
    with _scene(task.skill, task.scene, cfg, task.context_source, task.robot) as scene:
        t_move = movement_seconds(scene)
        base, log = _perturbed_run(scene, task, None, test)
        none = Perturbation("none")
        out = [_record(task, base, none, log, base, t_move, recipe, by_light)]
        for cond in task.conditions:
            if cond == "none":
                continue
            plan = draw_perturbation(cond, task.seed, base.movements, t_move)
            run, log = _perturbed_run(scene, task, plan, test)
            out.append(_record(task, run, plan, log, base, t_move, recipe, by_light))
    if "none" not in task.conditions:
        out = out[1:]
    return out


