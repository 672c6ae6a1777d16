"""The ``a2l demo`` job: the A2L pipeline end to end on a simulated Baxter.

1. The world: Baxter's right end-effector starts 15 cm in front of a box, gripper pointing
   down, and moves forward in discrete 5 cm movements (C++ inverse kinematics, joint
   position control) until the box moved; it prints how far (ground truth and camera).
2. A short push experiment on the Baxter scene (:mod:`a2l.experiments.push`): random
   babbling, Bayesian-network skills, closed-loop validation through the C++ step, one
   extension iteration; its results table and run directory.
3. ``a2l-run`` on the exported skill: the C++ runtime runs it in closed loop at control
   rate against the C++ virtual scene, and prints success and step-time figures.
4. Learning from demonstration (:func:`lfd_push`): a push skill learned from scripted
   demonstrations (vector field -> dataset -> the same Bayesian network and compiled table)
   runs on Baxter in the scene with a lamp while the box is moved mid-action and the light
   is switched; the demo prints the context and the movement the skill chose around each
   change.
5. A planned task (:func:`planned_task`): the light off and the block in the right-hand
   area, reached by a PDDL plan (pyperplan) of learned skills (grasp, press, through the C++
   step) joined by OMPL transits on Baxter; the light is switched back on behind the robot's
   back and the demo shows the replanning; it prints every plan and the plan files' directory.

Each part also writes what it printed as numbers into the run directory's ``demo.json``
(:data:`SUMMARY_FILE`; read by :func:`a2l.experiments.demo_report.summary_table`, the
``demo`` table of ``a2l results``); the demo ends by printing that table, part by part.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["SUMMARY_FILE", "lfd_push", "planned_task", "push_box", "run_demo"]

#: The demo's numbers, in its run directory.
SUMMARY_FILE = "demo.json"

#: The box must move at least this far (m) for the demo to succeed.
MIN_DISPLACEMENT = 0.01


def push_box(seed: int = 0, gui: bool = False, max_moves: int = 6,
             summary: dict[str, Any] | None = None) -> int:
    """Part 1 of the demo: Baxter pushes the box forward; print what happened.

    Parameters
    ----------
    seed : int
        Seed of the scene.
    gui : bool
        Open the PyBullet GUI and run in real time.
    max_moves : int
        Most forward movements to try.
    summary : dict, optional
        Receives ``moved_cm`` (ground truth), ``seen_cm`` (the camera; None when it did not
        see the box) and ``moves``.

    Returns
    -------
    int
        0 when the box moved at least :data:`MIN_DISPLACEMENT`, 1 when it did not, 2 when
        the scene could not be built (e.g. the GUI without a display).
    """
    from a2l.errors import A2LError
    from a2l.sim import make_scene

    t0 = time.perf_counter()
    try:
        scene = make_scene("push", seed=seed, gui=gui)
    except A2LError as exc:
        print(f"FAILED: cannot build the scene: {exc}")
        return 2
    with scene:
        box0 = np.asarray(scene.ground_truth()["objects"]["box"])
        seen0 = scene.perceive()["objects"].get("box")
        start = box0 + np.array([-0.15, 0.0, -0.01])
        scene.reset(eef=start)
        print(f"a2l demo (seed {seed}): Baxter's right gripper pushes a box in PyBullet, "
              "moving by the C++ inverse kinematics")
        print(f"  box at ({box0[0]:.3f}, {box0[1]:.3f}, {box0[2]:.3f}) m; end-effector starts "
              f"at ({start[0]:.3f}, {start[1]:.3f}, {start[2]:.3f}) m")
        i = 0
        for i in range(1, max_moves + 1):
            result = scene.execute((1, 0, 0))
            eef = result.reached
            effect = scene.observe_effect(source="ground_truth")
            print(f"  move {i}: +x {scene.step_length * 100:.0f} cm -> {result.status:<8} "
                  f"end-effector ({eef[0]:.3f}, {eef[1]:.3f}, {eef[2]:.3f}), effect {effect}")
            if not result:
                print(f"  movement not carried out: {result.message}")
                break
            if eef[0] > box0[0] + 0.02:
                break
        box1 = np.asarray(scene.ground_truth()["objects"]["box"])
        seen1 = scene.perceive()["objects"].get("box")
        moved = float(np.linalg.norm((box1 - box0)[:2]))
        seen: float | None = None
        print(f"  box moved {moved * 100:.1f} cm (ground truth), to "
              f"({box1[0]:.3f}, {box1[1]:.3f}, {box1[2]:.3f}) m; "
              f"effect over the episode: {scene.observe_effect('episode', 'ground_truth')}")
        if seen0 is not None and seen1 is not None:
            seen = float(np.linalg.norm((np.asarray(seen1) - np.asarray(seen0))[:2]))
            print(f"  the camera saw it move {seen * 100:.1f} cm")
    print(f"  ({time.perf_counter() - t0:.1f} s)")
    if summary is not None:
        summary.update(moved_cm=moved * 100, seen_cm=None if seen is None else seen * 100,
                       moves=i)
    if moved < MIN_DISPLACEMENT:
        print(f"FAILED: the box moved {moved * 1000:.1f} mm, less than "
              f"{MIN_DISPLACEMENT * 1000:.0f} mm")
        return 1
    print("OK: the box moved")
    return 0


def lfd_push(out: str | Path, seed: int = 1000, gui: bool = False,
             skill: str = "push_far", summary: dict[str, Any] | None = None) -> int:
    """Part 4 of the demo: a demonstrated push skill under perturbations, on Baxter.

    The skill is learned from its scripted demonstrations (:mod:`a2l.lfd.library`) and run
    through the C++ step in the ``press`` scene (the push box, a button and a lamp), from the
    held-out trial `seed`. After the 2nd movement the box is moved 4 cm sideways; after the
    3rd the light is switched on. Each step prints the context bins the skill saw and the
    movement it chose. `summary` receives ``skill``, ``effect``, ``movements``, ``stop``,
    ``success`` and the box's displacement ``produced_cm`` (x, y).

    Returns
    -------
    int
        0 when the box was pushed 5 cm the right way, 1 when not, 2 when the scene could not
        be built.
    """
    from a2l import _core
    from a2l.errors import A2LError
    from a2l.lfd.dataset import skill_discretizer
    from a2l.lfd.library import (
        SKILLS,
        learn_recipe,
        make_skill_scene,
        reset_for_trial,
        skill_config,
    )
    from a2l.rollout.run import run_skill

    t0 = time.perf_counter()
    recipe = SKILLS[skill]
    cfg = skill_config(skill)
    learned = learn_recipe(skill, Path(out), cfg)
    print(f"  {skill}: {cfg.n_demos} scripted demonstrations -> {learned.rows} rows -> "
          f"table over {learned.table.variables} ({time.perf_counter() - t0:.1f} s); "
          f"bundle {learned.bundle}")
    try:
        scene = make_skill_scene(skill, seed, scene="press", gui=gui)
    except A2LError as exc:
        print(f"FAILED: cannot build the scene: {exc}")
        return 2
    disc = skill_discretizer(cfg)
    core = _core.load_bundle(str(learned.bundle))
    events: dict[int, str] = {}

    def on_step(k: int, step: object) -> None:
        if k == 1:
            scene.perturb("move_object", name="box", delta=(0.0, -0.04))
            events[k] = "the box is moved 4 cm to the right (by hand, mid-action)"
        elif k == 2:
            scene.perturb("toggle", state="light")
            events[k] = (f"the light is switched {scene.ground_truth()['states']['light']} "
                         "(the push table has no light variable: the choice must not change)")

    with scene:
        reset_for_trial(scene, skill, seed)
        run = run_skill(scene, learned.bundle, recipe.effect, on_step=on_step)
        print(f"  Baxter, press scene (box, button, lamp), held-out trial seed {seed}; the "
              f"skill wants '{recipe.effect}'")
        for st in run.steps:
            bins = disc.context_bins(st.eef, st.obj)
            ctx = ", ".join(f"{k} {int(v[0])}" for k, v in bins.items())
            choice = st.label if st.status == "ok" else st.status
            extra = ""
            if st.status == "ok" and st.index > 0 and st.index - 1 in events:
                # what the C++ step chooses in this context with the light the other way
                other = dict(st.states)
                other["light"] = "off" if other.get("light") == "on" else "on"
                probe = _core.SkillState(core)
                out_ = _core.step(core, probe, core.context(st.eef, st.obj, recipe.effect,
                                                            other))
                alt = (core.movements.label(int(out_.movement))
                       if out_.status == _core.Status.ok else _core.status_name(out_.status))
                extra = f" (light {other['light']}: {alt})"
            print(f"    step {st.index}: box seen {np.linalg.norm(st.eef - st.obj) * 100:4.1f} "
                  f"cm away ({ctx}), light {st.states.get('light', '-')} -> {choice}{extra}")
            if st.index in events:
                print(f"    ** {events[st.index]}")
    print(f"  box pushed {run.produced[0] * 100:+.1f} cm along x, {run.produced[1] * 100:+.1f} "
          f"cm along y by the skill; {run.stop} after {run.movements} movements "
          f"({time.perf_counter() - t0:.1f} s)")
    if summary is not None:
        summary.update(skill=skill, effect=recipe.effect, movements=run.movements,
                       stop=run.stop, success=bool(run.success),
                       produced_cm=[float(run.produced[0]) * 100, float(run.produced[1]) * 100])
    if not run.success:
        print(f"FAILED: the skill did not push the box 5 cm {recipe.effect}")
        return 1
    print(f"OK: the box went {recipe.effect} despite the changes")
    return 0


def planned_task(out: str | Path, seed: int = 7000, gui: bool = False,
                 task: str = "light-off-place-right", fault: bool = True,
                 summary: dict[str, Any] | None = None) -> int:
    """Part 5 of the demo: a task planned with the learned skills, replanned after a fault.

    The grasp and press skills are learned (:func:`a2l.experiments.tasks.learn_task_skills`)
    and task `task` of :data:`a2l.experiments.tasks.TASKS` is played from trial `seed`
    (:func:`a2l.experiments.tasks.play_task`), with its fault when `fault`. `summary`
    receives ``task``, ``success``, ``replans``, ``skills`` (steps carried out), ``faults``
    (the faults injected), ``plan_ms`` and ``transit_ms`` (medians).

    Returns
    -------
    int
        0 when the goal was reached, 1 when not, 2 when the scene could not be built.
    """
    from a2l.errors import A2LError
    from a2l.experiments.tasks import TASKS, learn_task_skills, play_task

    t0 = time.perf_counter()
    out = Path(out)
    bundles = learn_task_skills(out / "skills")
    spec = TASKS[task]
    print(f"  skills grasp and press learned from demonstrations ({time.perf_counter() - t0:.1f}"
          f" s); operators grasp, press-light-on/off, and the scripted place, open-gripper, "
          "close-gripper")
    print(f"  task {task}: {spec.description}; trial seed {seed}"
          + (f", fault: {spec.fault}" if fault else ""))
    try:
        played = play_task(task, seed, fault, bundles, out / "plans", gui=gui)
    except A2LError as exc:
        print(f"FAILED: cannot build the scene: {exc}")
        return 2
    res = played.result
    print(f"  goal {played.goal}; start: light {played.light}")
    steps = iter(res.steps)
    for i, (plan, ms) in enumerate(zip(res.plans, res.plan_ms, strict=True)):
        head = "plan" if i == 0 else f"** replan {i} (the world disagreed)"
        print(f"  {head} (pyperplan, {ms:.0f} ms): " + " ".join(
            f"{k + 1}. {s}" for k, s in enumerate(plan)))
        for _ in plan:
            st = next(steps, None)
            if st is None:
                break
            ok = "as expected" if st.as_expected else (
                "NOT as expected: " + ", ".join(
                    [f"+{f}" for f in sorted(st.perceived - st.expected)]
                    + [f"-{f}" for f in sorted(st.expected - st.perceived)]))
            print(f"    {st.step}: {st.stop}; {ok}")
            if not st.as_expected:
                if played.fired:
                    print(f"    ** injected fault: {', '.join(played.fired)}")
                break
    print(f"  {res.report()}; OMPL transits {len(res.transit_ms)} (median "
          f"{np.median(res.transit_ms) if res.transit_ms else 0:.0f} ms planning); "
          f"plan files in {played.plan_dir}/ ({time.perf_counter() - t0:.1f} s)")
    if summary is not None:
        summary.update(task=task, success=bool(res.success), replans=len(res.plans) - 1,
                       skills=len(res.steps), faults=list(played.fired),
                       plan_ms=float(np.median(res.plan_ms)) if res.plan_ms else None,
                       transit_ms=float(np.median(res.transit_ms)) if res.transit_ms else None)
    if not res.success:
        print("FAILED: the planned task did not reach its goal")
        return 1
    print("OK: the planned task reached its goal")
    return 0


def _a2l_run(bundle: Path, seed: int, summary_path: Path | None = None) -> int:
    """Run ``a2l-run`` on `bundle` (virtual scene, through Baxter's arm) and echo it; its
    results as JSON to `summary_path` when given."""
    exe = shutil.which("a2l-run") or str(Path(sys.executable).with_name("a2l-run"))
    if not Path(exe).is_file():
        print("FAILED: the a2l-run executable is not installed (make setup)")
        return 2
    from a2l.robot import baxter_urdf

    cmd = [exe, str(bundle), "--scene", "virtual", "--episodes", "8", "--seed", str(seed),
           "--urdf", str(baxter_urdf()), "--trace", str(bundle.with_suffix(".trace.csv"))]
    if summary_path is not None:
        cmd += ["--summary", str(summary_path)]
    print("$ " + " ".join(["a2l-run", *cmd[1:]]), flush=True)
    return subprocess.run(cmd, check=False).returncode


def run_demo(seed: int = 0, gui: bool = False, out: str | Path | None = None,
             iterations: int = 3, starts: int = 8, workers: int | None = None) -> int:
    """The whole demo (see the module's docstring); returns the exit code.

    Parameters
    ----------
    seed : int
        Seed of every part.
    gui : bool
        Open the PyBullet GUI for part 1.
    out : path, optional
        Run directory (default ``runs/demo-<timestamp>``): the experiment's files, and
        :data:`SUMMARY_FILE` with every part's numbers and wall time, rewritten as each
        part ends (a failed part is recorded with its exit code).
    iterations : int
        Iterations of the push experiment.
    starts : int
        Start positions of the push experiment.
    workers : int, optional
        Worker processes for the rollouts (default: up to 2, one per core).
    """
    from a2l.experiments.demo_report import summary_table
    from a2l.progress import print_tables
    from a2l.rundir import make_run_dir, read_json, write_json

    workers = workers or max(1, min(2, os.cpu_count() or 1))
    run_dir = Path(make_run_dir("demo", out))
    t0 = time.perf_counter()
    summary: dict[str, Any] = {"seed": seed, "iterations": iterations, "starts": starts,
                               "workers": workers, "parts": {}}

    def part(name: str, fn: Any) -> int:
        rec: dict[str, Any] = {}
        t = time.perf_counter()
        rc = int(fn(rec))
        rec.update(rc=rc, wall_s=time.perf_counter() - t)
        summary["parts"][name] = rec
        summary["wall_s"] = time.perf_counter() - t0
        write_json(run_dir / SUMMARY_FILE, summary)
        return rc

    print("== 1/5  the world: Baxter pushes a box (PyBullet, C++ IK) ==")
    rc = part("world", lambda rec: push_box(seed=seed, gui=gui, summary=rec))
    if rc != 0:
        return rc
    print(f"\n== 2/5  A2L push experiment on the Baxter scene ({starts} starts, 4 effects, "
          f"{iterations} iterations) ==", flush=True)
    def experiment(rec: dict[str, Any]) -> int:
        from a2l.experiments.push import run_push_experiment
        from a2l.framework import FrameworkConfig

        # held-out starts in proportion to the training ones (the default 32 with 8 starts)
        cfg = FrameworkConfig(scene="bullet", discretization={"n_effects": 4},
                              starts={"n_starts": starts}, max_iterations=iterations,
                              seed=seed, heldout={"n_starts": 4 * starts})
        result = run_push_experiment(cfg, out=run_dir, workers=workers)
        rec.update(scores=[it["score"] for it in result["iterations"]],
                   success=result.get("final_success"),
                   heldout_success=result.get("heldout_success"),
                   heldout_score=result.get("heldout_score"),
                   bundle=str(Path(result["run_dir"]) / result["bundle"]))
        return 0

    part("experiment", experiment)
    bundle = Path(summary["parts"]["experiment"]["bundle"])
    print(f"\n== 3/5  a2l-run: the exported skill in the C++ runtime ({bundle.name}) ==",
          flush=True)

    def runtime(rec: dict[str, Any]) -> int:
        path = run_dir / "a2l-run.json"
        rc = _a2l_run(bundle, seed, path)
        if rc == 0:
            res = read_json(path)
            rec.update(success=res["success"], episodes=res["episodes"],
                       step_p50_us=res["step_time"]["p50_us"],
                       tick_p50_us=res["tick_time"]["p50_us"])
        return rc

    rc = part("runtime", runtime)
    if rc != 0:
        return rc
    print("\n== 4/5  learning from demonstration: a demonstrated push under perturbations "
          "(Baxter, PyBullet) ==", flush=True)
    rc = part("lfd", lambda rec: lfd_push(run_dir / "lfd", gui=gui, summary=rec))
    if rc != 0:
        return rc
    print("\n== 5/5  a planned task: PDDL plan of learned skills, OMPL transits, replanning "
          "(Baxter, PyBullet) ==", flush=True)
    rc = part("task", lambda rec: planned_task(run_dir / "task", gui=gui, summary=rec))
    print(f"\ndemo finished in {time.perf_counter() - t0:.0f} s; results in {run_dir}/ "
          f"(report.md, metrics.json, {SUMMARY_FILE}, plots, skills/); part by part:\n")
    print_tables(summary_table(summary))
    return rc
