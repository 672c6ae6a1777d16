"""The tasks of ``a2l experiment tasks`` and one trial of each (:mod:`a2l.experiments.tasks`).

:data:`TASKS` holds the task specs; :func:`play_task` plays one in a scene of its own (the
demo's last part uses it too); :func:`trial_task` turns a play into a row of ``trials.csv``.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from a2l.robot import DEFAULT_ROBOT
from a2l.rollout.protocol import SceneProtocol

__all__ = ["JITTER", "TASKS", "Played", "TaskSpec", "TaskTrial", "fault_hook",
           "learn_task_skills", "play_task", "task_skills", "trial_task"]

#: The block starts within ± this (m) of its start region's centre on each table axis.
JITTER = 0.03
_TASK_STREAM = 0x7461736B


@dataclass(frozen=True)
class TaskSpec:
    """One task of the experiment.

    Attributes
    ----------
    name : str
    description : str
    start_region : str
        Where the block starts (its centre ± :data:`JITTER`).
    gripper : {"open", "closed"}
        The gripper at the start.
    light : str or None
        The light at the start (None: drawn from the trial's seed).
    goal : callable ``(rng) -> str``
        The PDDL goal (the rng draws what the goal leaves open).
    fault : {"light_on", "drop", "move"}
        The injected fault: the light switched back on after the press, the block dropped
        after the grasp, the block moved to another region after the first step.
    """

    name: str
    description: str
    start_region: str
    gripper: str
    light: str | None
    goal: Callable[[np.random.Generator], str]
    fault: str


def _light(rng: np.random.Generator) -> str:
    return "on" if rng.uniform() < 0.5 else "off"


#: Task name -> spec.
TASKS: dict[str, TaskSpec] = {t.name: t for t in (
    TaskSpec("light-off-place-right", "switch the light off, grasp the block and put it in "
             "the right-hand area", "mid-centre", "open", "on",
             lambda _rng: "(and (light-off) (at block mid-right))", "light_on"),
    TaskSpec("tidy-light-on", "open the gripper, move the block to the middle, switch the "
             "light on, close the gripper", "close-right", "closed", "off",
             lambda _rng: "(and (light-on) (at block mid-centre) (gripper-closed) (hand-empty))",
             "drop"),
    TaskSpec("light-match", "make the light match a drawn goal state and bring the block "
             "close", "mid-right", "closed", None,
             lambda rng: f"(and (light-{_light(rng)}) (at block close-centre))", "move"),
)}

#: Regions a moved block may land in (the right arm reaches them with the gripper down).
_MOVE_TO = ("close-right", "mid-centre", "mid-right", "close-centre")


def _rng(seed: int, task: str, *extra: str) -> np.random.Generator:
    key = [int(seed), _TASK_STREAM, list(TASKS).index(task)]
    key += [sum(ord(c) for c in e) for e in extra]
    return np.random.default_rng(np.random.SeedSequence(key))


def task_skills() -> list[Any]:
    """The tasks' repertoire (planning operators): grasp, place, press-light-on/off (the
    press learned under any gripper state), open-gripper, close-gripper."""
    from a2l.planning import grasp_skill, gripper_skill, place_skill, press_skills

    return [grasp_skill(), place_skill(), *press_skills("light", ("on", "off"), learned_under={}),
            gripper_skill("open"), gripper_skill("closed")]


#: One ArmTransit per robot and process (its obstacles are synced per transit).
_TRANSITS: dict[Any, Any] = {}


def _transit(scene: Any) -> Any:
    """The transit planner of the scene's robot (:meth:`ArmTransit.for_scene`), made once."""
    entry = scene.robot_entry
    if entry not in _TRANSITS:
        from a2l.planning.transit import ArmTransit

        _TRANSITS[entry] = ArmTransit.for_scene(scene)
    return _TRANSITS[entry]


def fault_hook(spec: TaskSpec, rng: np.random.Generator, regions: Any, goal: str,
                fired: list[str], unchanged: list[str]) -> Callable[[int, Any, Any], None]:
    """The ``after_step`` hook that injects the task's fault once.

    :func:`a2l.planning.execute.execute_task` calls it only after a step whose perceived
    facts are the predicted ones, so a fault never follows a failed step (a press that did
    not switch the light off is not "undone" by switching the light off). A fault counts as
    applied (appended to `fired`) only when the facts perceived after it differ from those
    before it, i.e. the world disagrees with the plan; one that left them alike is recorded
    in `unchanged`. A moved block lands neither where it is nor in a region the goal names.
    """
    from a2l.planning.execute import perceive_state

    def facts(scene: SceneProtocol) -> frozenset[str]:
        return frozenset(perceive_state(scene, regions, objects=("block",)).facts())

    def hook(k: int, step: Any, scene: SceneProtocol) -> None:
        if fired:
            return
        before = facts(scene)
        if spec.fault == "light_on" and step.name == "press-light-off":
            scene.perturb("toggle", state="light")
        elif spec.fault == "drop" and step.name == "grasp":
            scene.execute("open")
        elif spec.fault == "move" and k == 0:
            pos = np.asarray(scene.ground_truth()["objects"]["block"], dtype=float)
            now = regions.region_of(pos[:2])
            choices = [r for r in _MOVE_TO if r != now and r not in goal]
            to = np.asarray(regions.center_of(choices[int(rng.integers(len(choices)))]))
            to = to + rng.uniform(-JITTER, JITTER, 2)
            scene.perturb("move_object", name="block", delta=tuple(to - pos[:2]))
        else:
            return
        (fired if facts(scene) != before else unchanged).append(f"{spec.fault}@{k}:{step}")

    return hook


@dataclass
class Played:
    """A task played once (:func:`play_task`).

    Attributes
    ----------
    result : a2l.planning.execute.TaskResult
    goal : str
    light : str
        The light at the start.
    fired : list of str
        The fault applied (``"<kind>@<step index>:<step>"``): after a step that carried out
        as planned, and the world then disagreed with the plan; empty without.
    unchanged : list of str
        Faults tried that left the perceived facts as planned (not applied).
    block : ndarray, shape (3,)
        Where the block ended.
    plan_dir : Path
        The domain, problem and plan files.
    trace : list of (str, ndarray, dict), optional
        With ``trace=True``: the end-effector (3,) and the objects (name -> (3,)) at the
        start (label ``""``) and after every executed plan step (label ``"<step>
        (<stop>)"``), from the simulator's truth.
    """

    result: Any
    goal: str
    light: str
    fired: list[str]
    block: np.ndarray
    plan_dir: Path
    unchanged: list[str] = field(default_factory=list)
    trace: list[tuple[str, np.ndarray, dict[str, np.ndarray]]] = field(default_factory=list)


def play_task(name: str, seed: int, fault: bool, bundles: dict[str, str],
              out: str | os.PathLike[str], planner: str = "pyperplan",
              time_limit: float = 10.0, max_replans: int = 3, gui: bool = False,
              context_source: str = "perceived", trace: bool = False,
              robot: str = DEFAULT_ROBOT) -> Played:
    """Play task `name` once from trial `seed`, in a scene of its own.

    Parameters
    ----------
    name : str
        A task of :data:`TASKS`.
    seed : int
        Trial seed (the start and the fault's draws).
    fault : bool
        Inject the task's fault.
    bundles : dict of str to path
        Operator -> skill bundle (``grasp``, ``press-light-on``, ``press-light-off``).
    out : path
        The plan files go to ``out/<task>-<seed>[-fault]/``.
    planner, time_limit, max_replans
        As :func:`a2l.planning.execute.execute_task`.
    gui : bool
        Open the PyBullet GUI.
    context_source : {"perceived", "ground_truth"}
        Where the skills and the planner's state read the scene: the camera (default) or
        the simulator's truth.
    trace : bool
        Keep where the arm and the objects were after every executed step
        (:attr:`Played.trace`, to record).
    robot : str
        The robot of the task scene (a built-in robot's name or a robot file,
        :func:`a2l.robot.robot_entry`); the transits are planned for its arm.

    Returns
    -------
    Played
    """
    from a2l.lfd.library import make_skill_scene
    from a2l.planning import TableRegions
    from a2l.planning.execute import execute_task

    spec = TASKS[name]
    rng = _rng(seed, spec.name)
    light = spec.light or _light(rng)
    goal = spec.goal(rng)
    jitter = rng.uniform(-JITTER, JITTER, 2)
    scene = make_skill_scene("grasp", seed, scene="task", states={"light": light}, gui=gui,
                             context_source=context_source, robot=robot)
    try:
        regions = TableRegions(tuple(scene.config.table_center), tuple(scene.config.table_size))
        start = np.asarray(regions.center_of(spec.start_region)) + jitter
        scene.reset(objects={"block": tuple(start)})
        if spec.gripper == "closed":
            scene.execute("close")
        fired: list[str] = []
        unchanged: list[str] = []
        hook = (fault_hook(spec, _rng(seed, spec.name, "fault"), regions, goal, fired,
                            unchanged) if fault else None)
        plan_dir = Path(out) / f"{spec.name}-{seed}{'-fault' if fault else ''}"
        seen: list[tuple[str, np.ndarray, dict[str, np.ndarray]]] = []

        def look(label: str, scene: Any) -> None:
            seen.append((label, np.asarray(scene.eef_position(), dtype=float),
                         {n: np.asarray(p, dtype=float)
                          for n, p in scene.ground_truth()["objects"].items()}))

        if trace:
            look("", scene)
        res = execute_task(scene, task_skills(), bundles, goal, plan_dir, regions=regions,
                           planner=planner, time_limit=time_limit, max_replans=max_replans,
                           transit=_transit(scene), seed=seed, after_step=hook, objects=("block",),
                           on_step=(lambda k, ex, sc: look(f"{ex.step} ({ex.stop})", sc))
                           if trace else None)
        block = np.asarray(scene.ground_truth()["objects"]["block"], dtype=float)
    finally:
        scene.close()
    return Played(res, goal, light, fired, block, plan_dir, unchanged, seen)


@dataclass(frozen=True)
class TaskTrial:
    """One trial of a task, as a worker plays it (:func:`trial_task`; the arguments of
    :func:`play_task`).

    Attributes
    ----------
    task : str
        The task (:data:`TASKS`).
    seed : int
        Trial seed (the start and the fault's draws).
    fault : bool
        Inject the task's fault.
    bundles : dict of str to str
        Operator -> skill bundle path (:func:`learn_task_skills`).
    out : str
        Where the plan files go (``out/<task>-<seed>[-fault]/``).
    planner : {"pyperplan", "fast-downward"}
        The PDDL planner.
    time_limit : float
        The planner's time limit per call (s).
    max_replans : int
        Replans allowed before giving up (:func:`a2l.planning.execute.execute_task`).
    context_source : {"perceived", "ground_truth"}
        Where the skills and the planner's state read the scene: the camera (default) or
        the simulator's truth.
    trace : bool
        The row then holds :attr:`Played.trace` as ``"trace"``, to record (not a column).
    robot : str
        The robot of the task scene (:func:`play_task`).
    """

    task: str
    seed: int
    fault: bool
    bundles: dict[str, str]
    out: str
    planner: str = "pyperplan"
    time_limit: float = 10.0
    max_replans: int = 3
    context_source: str = "perceived"
    trace: bool = False
    robot: str = DEFAULT_ROBOT


def trial_task(job: TaskTrial) -> dict[str, Any]:
    """Play one trial: a row of ``trials.csv``.

    Returns
    -------
    dict
        One row of ``trials.csv``. In a fault trial, ``fault_applied`` says whether the
        fault was applied (after a step that carried out as planned, and the world then
        disagreed with the plan); ``fault_not_applied`` says why not, otherwise empty.
    """
    t0 = time.perf_counter()
    seed = int(job.seed)
    fault = bool(job.fault)
    p = play_task(job.task, seed, fault, job.bundles, job.out, job.planner,
                  float(job.time_limit), int(job.max_replans),
                  context_source=job.context_source, trace=job.trace, robot=job.robot)
    res = p.result
    not_applied = ""
    if fault and not p.fired:
        not_applied = (f"left the world as planned: {';'.join(p.unchanged)}" if p.unchanged
                       else "the step it follows never carried out as planned")
    return {"task": job.task, "seed": seed, "fault": fault,
            "fault_injected": ";".join(p.fired), "fault_applied": bool(p.fired),
            "fault_not_applied": not_applied, "goal": p.goal, "light_start": p.light,
            "success": bool(res.success), "replans": int(res.replans),
            "skills_run": len(res.steps), "plan_len": len(res.plans[0]) if res.plans else 0,
            "plan": " ".join(res.plans[0]) if res.plans else "",
            "stops": ";".join(f"{s.step.name}:{s.stop}" for s in res.steps),
            "as_planned": "".join("1" if s.as_expected else "0" for s in res.steps),
            "unmet": ";".join(res.unmet), "message": res.message,
            "last_skill": res.last_skill or "",
            "plan_ms": float(np.sum(res.plan_ms)), "plan_calls": len(res.plan_ms),
            "plan_ms_first": float(res.plan_ms[0]) if res.plan_ms else float("nan"),
            "transit_ms": float(np.sum(res.transit_ms)), "transits": len(res.transit_ms),
            "transit_ms_max": float(np.max(res.transit_ms)) if res.transit_ms else 0.0,
            "block_x": float(p.block[0]), "block_y": float(p.block[1]),
            "wall_s": time.perf_counter() - t0, **({"trace": p.trace} if job.trace else {})}


def learn_task_skills(out_dir: str | os.PathLike[str]) -> dict[str, str]:
    """Learn the grasp and press skills (demonstration seeds 0 ..) into `out_dir`;
    returns operator -> bundle path."""
    from a2l.lfd.library import learn_recipe

    grasp = str(learn_recipe("grasp", out_dir).bundle)
    press = str(learn_recipe("press", out_dir).bundle)
    return {"grasp": grasp, "press-light-on": press, "press-light-off": press}
