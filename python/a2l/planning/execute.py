"""Closed-loop execution of a task: perceive, plan, run the plan skill after skill, replan.

:func:`execute_task` reaches a goal given as PDDL literals in a PyBullet scene:

1. perceive the state (:func:`perceive_state`: the light, the gripper, what it holds, which
   table region each movable object is in, from the scene's state as the skills see it);
2. write the problem (:func:`a2l.planning.problem_pddl`) and plan (:func:`a2l.planning.solve`,
   pyperplan by default, in the planner worker, killed at the time limit);
3. per plan step: move the arm above the step's object along a collision-free transit
   (:class:`a2l.planning.transit.ArmTransit`), run the learned skill in closed loop through
   the C++ step (:func:`a2l.rollout.run.run_skill`; its trace ends it early: ``step_cap``,
   ``unknown_context``...), perceive again and compare with the facts the step should give
   (:func:`a2l.planning.apply_step`);
4. an effect not produced, or a fact changed behind the robot's back, replans from the
   perceived state; the run ends in success when no goal literal is unmet, or in a failure
   report naming the unmet goal literals, the last skill and the number of replans.
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

import a2l
from a2l import _core
from a2l.errors import A2LValueError
from a2l.planning.pddl import PerceivedState, Skill, domain_pddl, problem_pddl
from a2l.planning.planners import PlanStep, solve
from a2l.planning.repertoire import TableRegions
from a2l.planning.simulate import apply_step, goal_literals, unmet
from a2l.rollout.protocol import ArmSceneProtocol, SceneProtocol
from a2l.rollout.run import run_skill
from a2l.rollout.world import observe

__all__ = ["APPROACH", "SCRIPTED", "ExecutedStep", "TaskResult", "execute_task", "perceive_state"]

#: Where a skill starts, relative to its object (m): above it, inside the start
#: distribution the manipulation skills were demonstrated from.
APPROACH = np.array([-0.02, 0.0, 0.18])
#: How far (m) the end-effector rises straight up before a transit, clear of what the last
#: skill touched (the transit's start must be out of its padded obstacles).
CLEARANCE = 0.06
#: Operator kinds carried out by a scripted primitive, not a learned skill bundle: the
#: gripper's open/close, and ``place`` (no place skill was demonstrated; see :func:`_place`).
SCRIPTED = ("gripper", "place")
#: Height (m) of the held object's bottom above the table where ``place`` arrives by transit.
PLACE_HEIGHT = 0.10
#: ``place`` lowers the held object until its bottom is this close to the table (m).
PLACE_GAP = 0.01
#: A transit's goal: after 10 IK starts near the current and neutral poses, this many starts
#: drawn wider (normal, this sigma in rad around the neutral pose) before ``goal_in_collision``.
WIDE_IK_STARTS = 16
WIDE_IK_SIGMA = 1.0


def perceive_state(scene: SceneProtocol, regions: TableRegions, static: Sequence[str] = (),
                   source: str | None = None,
                   objects: Sequence[str] | None = None) -> PerceivedState:
    """The planner's state from the scene.

    Parameters
    ----------
    scene : a2l.sim.Scene
    regions : TableRegions
        The table's regions (an object off the table is in none and left out).
    static : sequence of str
        Static facts (region neighbourhood).
    source : {"perceived", "ground_truth"}, optional
        Where positions and states come from (default: the scene's ``context_source``,
        the camera unless the scene says ground truth).
    objects : sequence of str, optional
        The movable objects the planner may act on (default: every object of the scene
        but the button).

    Returns
    -------
    PerceivedState
        Movable objects with their region (None while held), the button (if any), the
        high-level states (``light``, ``gripper``) and the held object: one in the closed
        gripper (within 8 cm of the end-effector) and more than the scene's
        ``lift_threshold`` above the table.
    """
    obs = observe(scene, source)
    states = dict(obs["states"])
    cfg = scene.config
    lift = float(getattr(cfg, "lift_threshold", _core.LIFT_THRESHOLD))
    eef = np.asarray(scene.eef_position(), dtype=float)
    movables: dict[str, str | None] = {}
    holding = None
    for name, pos in obs["objects"].items():
        if name == "button" or pos is None or (objects is not None and name not in objects):
            continue
        xyz = np.asarray(pos, dtype=float)
        size = getattr(cfg, f"{name}_size", (0.0, 0.0, 0.0))
        rest_z = cfg.table_z + size[2] / 2
        if states.get("gripper") == "closed" and xyz[2] - rest_z > lift and \
                np.linalg.norm(xyz - eef) < 0.08:
            holding, movables[name] = name, None
            continue
        region = regions.region_of(xyz[:2])
        if region is not None:
            movables[name] = region
    buttons = ("button",) if "button" in scene.object_names else ()
    return PerceivedState(regions.names, movables, buttons, states, holding, tuple(static))


@dataclass
class ExecutedStep:
    """One plan step as carried out.

    Attributes
    ----------
    step : PlanStep
    stop : str
        Why the skill ended (:attr:`a2l.rollout.run.SkillRun.stop`, ``"done"`` for a gripper
        primitive, ``"transit:<status>"`` when the arm could not get to the start).
    expected, perceived : frozenset of str
        Facts the step should give and facts perceived after it.
    """

    step: PlanStep
    stop: str
    expected: frozenset[str]
    perceived: frozenset[str]

    @property
    def as_expected(self) -> bool:
        """The perceived facts are the predicted ones."""
        return self.expected == self.perceived


@dataclass
class TaskResult:
    """How a task ended.

    Attributes
    ----------
    success : bool
    goal : str
    unmet : list of str
        Goal literals that do not hold at the end.
    last_skill : str or None
        The last plan step run (None if none ran).
    replans : int
        Plans made after the first one.
    steps : list of ExecutedStep
    message : str
        A failure report (empty on success).
    plan_ms : list of float
        Wall time of each planner call (ms; the planner worker's start-up when the call
        started it).
    transit_ms : list of float
        OMPL planning time of each transit (ms; path shortening and time parameterisation
        included, the arm's movement not).
    plans : list of list of str
        Every plan made, its steps as PDDL text.
    """

    success: bool
    goal: str
    unmet: list[str]
    last_skill: str | None
    replans: int
    steps: list[ExecutedStep] = field(default_factory=list)
    message: str = ""
    plan_ms: list[float] = field(default_factory=list)
    transit_ms: list[float] = field(default_factory=list)
    plans: list[list[str]] = field(default_factory=list)

    def report(self) -> str:
        """One line for humans."""
        if self.success:
            return (f"goal {self.goal} reached in {len(self.steps)} skills, "
                    f"{self.replans} replans")
        return (f"goal {self.goal} NOT reached: unmet {', '.join(self.unmet)}; last skill "
                f"{self.last_skill}; {self.replans} replans; {self.message}")


def _transit_to(scene: ArmSceneProtocol, transit: Any, target: np.ndarray, held: tuple[str, ...],
                seed: int, times: list[float]) -> str:
    """Move the arm to the end-effector position `target` (3,); returns ``"ok"`` or why not.
    The OMPL planning time (ms) is appended to `times`."""
    for _ in range(int(round(CLEARANCE / scene.step_length))):  # up, clear of what it touched
        if not scene.execute_displacement([0.0, 0.0, scene.step_length]).carried_out:
            break
    q0 = scene.joint_positions()
    transit.sync(scene, ignore=held)
    # IK from the current joints, the neutral pose, then seeded random starts: the first
    # collision-free solution. Starts near the neutral pose may all land the elbow in the
    # torso (above the button, every one of 10 did): wider starts follow.
    rng = np.random.default_rng(seed)
    neutral = scene.neutral_joint_positions
    starts = itertools.chain(
        [q0, neutral], (neutral + rng.normal(0.0, 0.5, neutral.shape) for _ in range(8)),
        (neutral + rng.normal(0.0, WIDE_IK_SIGMA, neutral.shape) for _ in range(WIDE_IK_STARTS)))
    q1, why = None, "ik_failed"
    for start in starts:
        q, rep = scene.kinematics.ik_report(scene.gripper_down_pose(target), start)
        if rep.status != a2l.Status.ok:
            continue
        if transit.in_collision(q):
            why = "goal_in_collision"
            continue
        q1 = q
        break
    if q1 is None:
        return why
    plan = transit.plan(q0, q1, seed=seed)
    times.append(1000.0 * plan.planning_time)
    if not plan.ok:
        return plan.status
    err = scene.follow_joint_trajectory(plan.times, plan.positions)
    return "ok" if err < 0.05 else "not_reached"


def execute_task(scene: ArmSceneProtocol, skills: Sequence[Skill],
                 bundles: Mapping[str, str | os.PathLike[str]],
                 goal: str, out_dir: str | os.PathLike[str], regions: TableRegions | None = None,
                 planner: str = "pyperplan", time_limit: float = 10.0, max_replans: int = 3,
                 transit: Any = None, seed: int = 0,
                 after_step: Callable[[int, PlanStep, Any], None] | None = None,
                 static: Sequence[str] = (), objects: Sequence[str] | None = None,
                 on_step: Callable[[int, ExecutedStep, Any], None] | None = None
                 ) -> TaskResult:
    """Reach `goal` in `scene` with the learned skills, replanning when the world disagrees.

    Parameters
    ----------
    scene : a2l.sim.bullet.BulletScene
        A PyBullet scene (``"task"``: button, lamp, block), its movement length the bundles'.
    skills : sequence of Skill
        The repertoire (planning operators).
    bundles : mapping of str to path
        Operator name -> skill bundle that runs it (kind ``press``, ``grasp``, ``push``...);
        the scripted kinds (:data:`SCRIPTED`: ``gripper``, ``place``) need none.
    goal : str
        PDDL goal: one atom or ``(and ...)`` of atoms.
    out_dir : path
        Where each plan's domain, problem and plan files are written (``plan<k>-...``).
    regions : TableRegions, optional
        Default: the scene's table cut 3 x 3.
    planner : {"pyperplan", "fast-downward"}
    time_limit : float
        Per planner call (s).
    max_replans : int
        Replans allowed before giving up.
    transit : ArmTransit, optional
        Default: a new one for the scene's robot (:meth:`ArmTransit.for_scene`).
    seed : int
        Transit planner seed.
    after_step : callable ``(k, step, scene) -> None``, optional
        Called after plan step k (counted over every plan) when its perceived facts are the
        predicted ones, never after a step that failed; the world is perceived again after
        it (a test or an experiment injects faults here).
    static : sequence of str
        Static facts (region neighbourhood for push skills).
    objects : sequence of str, optional
        The movable objects the planner may act on (default: all; see
        :func:`perceive_state`).
    on_step : callable ``(k, executed, scene) -> None``, optional
        Called after every plan step k (as planned or not, after `after_step`) with how it
        ended (:class:`ExecutedStep`); it only looks (e.g. a recording).

    Returns
    -------
    TaskResult

    Raises
    ------
    a2l.A2LValueError
        A plan step whose skill has no bundle, a bad goal (unknown predicate or object).
    """
    regions = regions or TableRegions(tuple(scene.config.table_center),
                                      tuple(scene.config.table_size))
    missing = sorted(s.name for s in skills
                     if s.kind not in SCRIPTED and s.name not in bundles)
    if missing:
        raise A2LValueError(f"execute_task: no skill bundle for operators {missing}")
    if transit is None:
        from a2l.planning.transit import ArmTransit

        transit = ArmTransit.for_scene(scene)
    goal_literals(goal)
    domain = domain_pddl(skills)
    by_name = {s.name: s for s in skills}
    out = Path(out_dir)
    result = TaskResult(False, goal, [], None, 0)
    k = 0
    for attempt in range(max_replans + 1):
        state = perceive_state(scene, regions, static, objects=objects)
        facts = frozenset(state.facts())
        result.unmet = unmet(goal, facts)
        if not result.unmet:
            result.success = True
            return result
        result.replans = attempt
        plan = solve(domain, problem_pddl(skills, state, goal), out, planner, time_limit,
                     name=f"plan{attempt}")
        result.plan_ms.append(1000.0 * plan.time_s)
        result.plans.append([str(s) for s in plan.plan])
        if not plan.solved:
            result.message = f"planner: {plan.report()}"
            return result
        for step in plan.plan:
            skill = by_name[step.name]
            expected = apply_step(skills, facts, step)
            stop = _run_step(scene, skill, step, bundles, transit, state, seed + k, run_skill,
                             regions, result.transit_ms)
            result.last_skill = str(step)
            state = perceive_state(scene, regions, static, objects=objects)
            now = frozenset(state.facts())
            if after_step is not None and now == expected:
                # only a step that carried out as planned is followed by the hook; what it
                # changed is perceived (and replanned) like any change behind the robot's back
                after_step(k, step, scene)
                state = perceive_state(scene, regions, static, objects=objects)
                now = frozenset(state.facts())
            k += 1
            result.steps.append(ExecutedStep(step, stop, expected, now))
            if on_step is not None:
                on_step(k - 1, result.steps[-1], scene)
            facts = now
            if now != expected:
                break  # an effect not produced or a world changed: replan
    state = perceive_state(scene, regions, static, objects=objects)
    result.unmet = unmet(goal, state.facts())
    result.success = not result.unmet
    if not result.success:
        result.message = f"gave up after {max_replans} replans"
    return result


def _place(scene: ArmSceneProtocol, transit: Any, step: PlanStep, regions: TableRegions, seed: int,
           times: list[float]) -> str:
    """The scripted ``place`` primitive: carry the held object above the centre of the
    step's region (transit), lower it until it is within :data:`PLACE_GAP` of the table,
    open the gripper; returns ``"done"`` or why not."""
    obj, region = step.args[0], step.args[-1]
    cfg = scene.config
    size = getattr(cfg, f"{obj}_size", (0.0, 0.0, 0.0))
    cx, cy = regions.center_of(region)
    held_z = float(scene.eef_position()[2] - scene.ground_truth()["objects"][obj][2])
    above = np.array([cx, cy, cfg.table_z + size[2] / 2 + PLACE_HEIGHT + held_z])
    status = _transit_to(scene, transit, above, (obj,), seed, times)
    if status != "ok":
        return f"transit:{status}"
    for _ in range(int(np.ceil(PLACE_HEIGHT / scene.step_length)) + 2):
        z = float(scene.ground_truth()["objects"][obj][2])
        if z - size[2] / 2 - cfg.table_z <= PLACE_GAP:
            break
        if not scene.execute_displacement([0.0, 0.0, -scene.step_length]).carried_out:
            break
    res = scene.execute("open")
    return "done" if res.carried_out else res.status


def _run_step(scene: ArmSceneProtocol, skill: Skill, step: PlanStep, bundles: Mapping[str, Any],
              transit: Any, state: PerceivedState, seed: int, run_skill: Any,
              regions: TableRegions, times: list[float]) -> str:
    """Carry out one plan step; returns why it stopped."""
    if skill.kind == "gripper":
        res = scene.execute("open" if skill.effect == "open" else "close")
        return "done" if res.carried_out else res.status
    if skill.kind == "place":
        return _place(scene, transit, step, regions, seed, times)
    obj = next((a for a in step.args if a in scene.object_names), None)
    if obj is None:
        raise A2LValueError(f"plan step {step}: none of its arguments is an object of scene "
                            f"{scene.name!r} ({list(scene.object_names)})")
    pos = np.asarray(scene.ground_truth()["objects"][obj], dtype=float)
    held = (state.holding,) if state.holding else ()
    status = _transit_to(scene, transit, pos + APPROACH, held, seed, times)
    if status != "ok":
        return f"transit:{status}"
    scene.start_episode()  # the skill's effect test counts from here
    run = run_skill(scene, bundles[skill.name], skill.effect, object_name=obj)
    return run.stop
