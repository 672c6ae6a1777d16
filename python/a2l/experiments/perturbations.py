"""``a2l experiment perturbations``: demonstrated skills under perturbations (issue 11, part 5).

Every skill of :data:`a2l.lfd.library.SKILLS` is demonstrated (demonstration seeds
``0 .. n_demos - 1``), learned (:func:`a2l.lfd.library.learn_recipe`) and run in closed loop
on Baxter in PyBullet from held-out trial seeds (default ``5000 .. 5049``: no demonstration,
no tuning and no other experiment used them), under four conditions:

- ``none``: no perturbation;
- ``move_object``: mid-action, the object is teleported 3-5 cm in a random direction on the
  table;
- ``hold``: mid-action, the end-effector is held for 1-2 s: the skill goes on commanding
  movements, the arm does not move (:meth:`a2l.sim.Scene.perturb` ``"hold"``, one movement's
  time per commanded movement);
- ``toggle_light``: mid-action, the light is switched. A skill that does not depend on the
  light must do exactly what it did without the toggle; the light-dependent grasp must do
  what its demonstration under the new state did (grasp with the light off, move away and
  wait with it on).

Each condition runs twice: the context skill (the compiled table, ``mode="table"``) and the
DS alone (``mode="ds"``). A trial task is one (skill, mode, seed): it runs ``none`` first;
the perturbed runs replay it (same seed, same start: the runs are identical up to the
perturbation, which the task checks) and perturb after movement ``m``, ``m`` drawn from the
trial's seed between one and two thirds of the unperturbed run's movements. Every
perturbation draw comes from ``(seed, condition)`` only, so results do not depend on the
workers (one, two or a Dask cluster give the same metrics).

Scenes: a skill runs in its recipe's scene if that scene has a light, else in the scene
with the same object and a lamp (``push`` -> ``press``: the box and a button with its lamp;
``grasp`` -> ``grasp_light``), so the toggle really switches a light; every condition of a
skill uses the same scene. Context from the ground truth (as :func:`make_skill_scene`).

Effect tests: the recipe's, except ``pressed`` (counted from the button's presses, since the
toggle itself switches the light) and the light-dependent skill (the test of the effect its
demonstrations produced under the light state now seen).

Output: ``skills/*.a2lb``, ``config.json``, ``trials.csv`` (one row per run),
``trajectories.npz``, ``metrics.json`` (``skills -> skill -> condition -> {context, ds,
mean_steps, ...}``), ``report.md`` and one plot per skill and condition
(:mod:`a2l.experiments.perturbation_report`).
"""

from __future__ import annotations

import argparse
import io
import math
import os
import shlex
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from a2l.lfd.config import DEFAULT, LfDConfig

__all__ = ["CONDITIONS", "MODES", "Perturbation", "add_parser", "draw_perturbation",
           "run_perturbations", "skill_scene", "trial_task"]

#: The perturbation conditions, in report order.
CONDITIONS = ("none", "move_object", "hold", "toggle_light")
#: Execution modes: the context skill (table) and the DS alone.
MODES = ("table", "ds")
#: First trial seed by default (held out: demonstrations use 0 .. n_demos - 1,
#: ``a2l experiment lfd-skills`` 1000 ...).
DEFAULT_SEED = 5000
#: A scene without a light -> the scene with the same object and a lamp.
LIT_SCENES = {"push": "press", "grasp": "grasp_light"}
#: Light value -> effect demonstrated under it, for skills whose table has the light
#: (unless the recipe's ``extra["effect_by_light"]`` says otherwise).
EFFECT_BY_LIGHT = {"off": "grasped", "on": "away"}
#: Mid-action: after a movement between these fractions of the unperturbed run.
WINDOW = (1 / 3, 2 / 3)
MOVE_RANGE = (0.03, 0.05)  # m
HOLD_RANGE = (1.0, 2.0)    # s

_PERTURB_STREAM = 0x70657274  # perturbation draws apart from the trial's start draws
_SCENES: dict[str, Any] = {}  # one scene per worker process, keyed by scene and step


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


def movement_seconds(scene: Any) -> float:
    """Simulated time of one movement (and of one held movement) in a Baxter scene (s)."""
    cfg = scene.config
    return max(1, round(cfg.step / cfg.speed / cfg.time_step)) * cfg.time_step


def light_effects(recipe: Any) -> dict[str, str] | None:
    """Light value -> expected effect for a skill whose table has the light, else None."""
    if not any(getattr(h, "name", None) == "light" for h in recipe.high_level):
        return None
    return dict(recipe.extra.get("effect_by_light", EFFECT_BY_LIGHT))


def _effect_test(effect: str) -> Callable[[Any], tuple[bool, bool]]:
    from a2l.lfd.execute import EFFECT_TESTS, scene_test
    from a2l.sim.outcomes import EFFECT_TESTS as SCENE_TESTS

    if effect == "pressed":  # pressed by the robot: the toggle alone is no press
        def pressed(pr: Any) -> tuple[bool, bool]:
            ok = pr.scene.presses > 0
            return ok, ok
        return pressed
    if effect in EFFECT_TESTS:
        return EFFECT_TESTS[effect]
    if effect in SCENE_TESTS:
        return scene_test(SCENE_TESTS[effect])
    raise ValueError(f"no effect test for {effect!r}")


def _skill_test(recipe: Any) -> Callable[[Any], tuple[bool, bool]]:
    by_light = light_effects(recipe)
    if by_light is None:
        return _effect_test(recipe.effect)
    tests = {v: _effect_test(e) for v, e in by_light.items()}
    return lambda pr: tests[pr.states.get("light", "off")](pr)


def _scene(skill: str, scene_name: str, cfg: LfDConfig) -> Any:
    from a2l.lfd.library import make_skill_scene

    key = repr((scene_name, cfg.step))
    if key not in _SCENES:
        for old in _SCENES.values():
            old.close()
        _SCENES.clear()
        _SCENES[key] = make_skill_scene(skill, 0, cfg, scene=scene_name)
    return _SCENES[key]


def _truth(scene: Any, name: str) -> np.ndarray:
    return np.asarray(scene.ground_truth()["objects"][name], dtype=float)


def _perturbed_run(scene: Any, task: dict[str, Any], plan: Perturbation | None
                   ) -> tuple[Any, dict[str, Any]]:
    """Reset for the trial and run the skill, applying `plan` after its step."""
    from a2l.lfd.execute import run_skill
    from a2l.lfd.library import SKILLS, reset_for_trial

    recipe = SKILLS[task["skill"]]
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

    reset_for_trial(scene, task["skill"], task["seed"])
    run = run_skill(scene, task["bundle"], recipe.effect, mode=task["mode"],
                    on_step=on_step, effect_test=_skill_test(recipe), object_name=obj)
    return run, log


def _record(task: dict[str, Any], run: Any, plan: Perturbation, log: dict[str, Any],
            base: Any, movement_s: float, recipe: Any) -> dict[str, Any]:
    """One row of ``trials.csv`` (plus the trajectories, kept apart)."""
    after = plan.after if log["applied"] else 0
    row: dict[str, Any] = {
        "skill": task["skill"], "mode": task["mode"], "condition": plan.condition,
        "seed": task["seed"], "success": bool(run.success), "stop": run.stop,
        "movements": int(run.movements), "steps": len(run.steps) - 1,
        "applied": bool(log["applied"]), "after": after,
        "displacement_m": np.nan, "hold_s": np.nan, "hold_planned_s": np.nan,
        "held_observed": 0,
        "hold_drift_m": np.nan, "light_before": log.get("light_before", ""),
        "light_after": log.get("light_after", ""),
        "prefix_identical": True, "same_as_none": True, "expected_effect": recipe.effect,
        "light_dependent": light_effects(recipe) is not None,
    }
    if plan.condition != "none":
        n = min(after + 1, len(base.eef), len(run.eef)) if after else 0
        row["prefix_identical"] = bool(np.array_equal(run.eef[:n], base.eef[:n]))
        row["same_as_none"] = bool(run.eef.shape == base.eef.shape
                                   and np.array_equal(run.eef, base.eef)
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
    by_light = light_effects(recipe)
    if by_light is not None:
        light = row["light_after"] or run.steps[0].states.get("light", "off")
        row["expected_effect"] = by_light.get(light, recipe.effect)
    row["eef"], row["obj"] = run.eef, run.obj
    return row


def trial_task(task: dict[str, Any]) -> list[dict[str, Any]]:
    """One trial: ``{"skill", "bundle", "mode", "seed", "scene", "conditions", "cfg"}``.

    Runs the skill without perturbation, then under each other condition from the same
    start; returns one record per condition (``none`` first).
    """
    from a2l.lfd.library import SKILLS

    cfg = LfDConfig(**task["cfg"])
    recipe = SKILLS[task["skill"]]
    scene = _scene(task["skill"], task["scene"], cfg)
    t_move = movement_seconds(scene)
    base, log = _perturbed_run(scene, task, None)
    none = Perturbation("none")
    out = [_record(task, base, none, log, base, t_move, recipe)]
    for cond in task["conditions"]:
        if cond == "none":
            continue
        plan = draw_perturbation(cond, task["seed"], base.movements, t_move)
        run, log = _perturbed_run(scene, task, plan)
        out.append(_record(task, run, plan, log, base, t_move, recipe))
    if "none" not in task["conditions"]:
        out = out[1:]
    return out


def _learn(job: tuple[str, str, dict[str, Any]]) -> dict[str, Any]:
    from a2l.lfd.library import learn_recipe

    name, out_dir, cfg = job
    t0 = time.perf_counter()
    learned = learn_recipe(name, out_dir, LfDConfig(**cfg))
    return {"skill": name, "bundle": str(learned.bundle), "rows": int(learned.rows),
            "seconds": time.perf_counter() - t0}


def _check(skills: Sequence[str], conditions: Sequence[str], trials: int, seed: int,
           workers: int, cfg: LfDConfig) -> None:
    """Raise ValueError naming the first bad argument."""
    from a2l.lfd.library import SKILLS

    unknown = [s for s in skills if s not in SKILLS]
    if unknown or not skills:
        raise ValueError(f"--skills: unknown skill(s) {unknown}; known: {sorted(SKILLS)}")
    bad = [c for c in conditions if c not in CONDITIONS]
    if bad or not conditions:
        raise ValueError(f"--conditions: unknown condition(s) {bad}; known: {list(CONDITIONS)}")
    if trials < 1:
        raise ValueError(f"--trials: must be >= 1, got {trials}")
    if workers < 1:
        raise ValueError(f"--workers: must be >= 1, got {workers}")
    if seed < cfg.n_demos:
        raise ValueError(f"--seed: trial seeds {seed}.. overlap the demonstration seeds "
                         f"0..{cfg.n_demos - 1}; use a seed >= {cfg.n_demos} "
                         f"(default {DEFAULT_SEED})")


def run_perturbations(out: str | os.PathLike[str], skills: Sequence[str] | None = None,
                      trials: int = 50, seed: int = DEFAULT_SEED, workers: int = 1,
                      cluster: str | None = None, conditions: Sequence[str] = CONDITIONS,
                      cfg: LfDConfig = DEFAULT, bundles: dict[str, str] | None = None,
                      quiet: bool = False, plots: bool = True,
                      command: str | None = None) -> dict[str, Any]:
    """Learn the skills, run every trial under every condition and write the run directory.

    Parameters
    ----------
    out : path
        Run directory.
    skills : sequence of str, optional
        Default: every skill of :data:`a2l.lfd.library.SKILLS`.
    trials : int
        Trials (seeds ``seed .. seed + trials - 1``) per skill, condition and mode.
    seed : int
        First trial seed (>= ``cfg.n_demos``).
    workers, cluster
        Where trials run (:class:`a2l.parallel.Executor`).
    conditions : sequence of str
        Subset of :data:`CONDITIONS`.
    cfg : LfDConfig
        The pipeline's configuration.
    bundles : dict of str to path, optional
        Already learned bundles (skill -> path): not learned again.
    quiet, plots : bool
        No progress bar / no figures.
    command : str, optional
        The command line recorded in the report.

    Returns
    -------
    dict
        The content of ``metrics.json``.
    """
    from a2l.experiments.lfd_skills import progress_bar
    from a2l.experiments.perturbation_report import summarise, write_report
    from a2l.experiments.rundir import atomic_write_bytes, atomic_write_text, make_run_dir
    from a2l.experiments.rundir import write_json
    from a2l.lfd.library import SKILLS
    from a2l.parallel import Executor

    names = list(skills) if skills else list(SKILLS)
    conds = [c for c in CONDITIONS if c in conditions] if conditions else []
    _check(names, list(conditions), trials, seed, workers, cfg)
    out_path = Path(out)
    if out_path.exists() and not out_path.is_dir():
        raise ValueError(f"--out: '{out_path}' exists and is not a directory")
    run_dir = make_run_dir("perturbations", out_path)
    seeds = list(range(seed, seed + trials))
    scenes = {n: skill_scene(SKILLS[n]) for n in names}
    command = command or shlex.join(
        ["a2l", "experiment", "perturbations", "--out", str(run_dir), "--skills",
         ",".join(names), "--trials", str(trials), "--seed", str(seed), "--workers",
         str(workers)] + (["--cluster", cluster] if cluster else [])
        + ([] if conds == list(CONDITIONS) else ["--conditions", ",".join(conds)]))
    config = {"experiment": "perturbations", "skills": names, "conditions": conds,
              "modes": list(MODES), "trial_seeds": [seeds[0], seeds[-1]],
              "demonstration_seeds": [0, cfg.n_demos - 1], "scenes": scenes,
              "window": list(WINDOW), "move_m": list(MOVE_RANGE), "hold_s": list(HOLD_RANGE),
              "lfd": cfg.to_json(), "workers": workers, "cluster": cluster,
              "command": command}
    write_json(run_dir / "config.json", config)
    t0 = time.perf_counter()
    with Executor(workers, cluster) as ex:
        todo = [n for n in names if not bundles or n not in bundles]
        learned = ex.map(_learn, [(n, str(run_dir / "skills"), cfg.to_json()) for n in todo])
        learning = {r["skill"]: r for r in learned}
        paths = {**{n: str(b) for n, b in (bundles or {}).items() if n in names},
                 **{r["skill"]: r["bundle"] for r in learned}}
        tasks = [{"skill": n, "bundle": paths[n], "mode": m, "seed": s, "scene": scenes[n],
                  "conditions": conds, "cfg": cfg.to_json()}
                 for n in names for m in MODES for s in seeds]
        with progress_bar("perturbation trials", len(tasks), quiet) as bar:
            results = ex.map(trial_task, tasks, on_done=bar)
    rows = [r for chunk in results for r in chunk]
    wall = time.perf_counter() - t0
    trajectories = {f"{r['skill']}/{r['condition']}/{r['mode']}/{r['seed']}/{k}": r.pop(k)
                    for r in rows for k in ("eef", "obj")}
    buf = io.BytesIO()
    np.savez_compressed(buf, **trajectories)
    atomic_write_bytes(run_dir / "trajectories.npz", buf.getvalue())
    frame = pd.DataFrame(rows)
    atomic_write_text(run_dir / "trials.csv", frame.to_csv(index=False))
    metrics = {"experiment": "perturbations", "trial_seeds": config["trial_seeds"],
               "demonstration_seeds": config["demonstration_seeds"], "scenes": scenes,
               "skills": summarise(frame), "learning": learning, "wall_s": wall,
               "workers": workers}
    write_json(run_dir / "metrics.json", metrics)
    text = write_report(run_dir, metrics, config, frame, trajectories, plots=plots)
    if not quiet:
        print(text)
        print(f"results in {run_dir}/ (report.md, metrics.json, trials.csv, plots)")
    return metrics


def _cmd(args: argparse.Namespace) -> int:
    from a2l.cli import UsageError

    def split(s: str | None) -> list[str] | None:
        return [x.strip() for x in s.split(",") if x.strip()] if s else None

    try:
        run_perturbations(args.out, split(args.skills), args.trials, args.seed, args.workers,
                          args.cluster, split(args.conditions) or CONDITIONS,
                          quiet=args.quiet, plots=not args.no_plots)
    except ValueError as exc:
        arg, _, msg = str(exc).partition(": ")
        if not arg.startswith("--"):
            raise
        raise UsageError(arg, msg) from None
    return 0


def add_parser(exps: argparse._SubParsersAction) -> None:
    """Register ``a2l experiment perturbations``."""
    p = exps.add_parser(
        "perturbations", help="demonstrated skills under perturbations: context skill vs DS",
        description="Learn each demonstrated skill, then run it on held-out trial seeds "
        "without perturbation and with the object moved 3-5 cm, the end-effector held 1-2 s "
        "and the light switched mid-action, each as the context skill (table) and as the DS "
        "alone; write metrics.json, trials.csv, report.md and trajectory plots.")
    p.add_argument("--out", required=True, help="run directory")
    p.add_argument("--skills", default=None,
                   help="comma-separated skill names (default: every registered skill)")
    p.add_argument("--conditions", default=None,
                   help=f"comma-separated subset of {','.join(CONDITIONS)} (default: all)")
    p.add_argument("--trials", type=int, default=50,
                   help="trials per skill, condition and mode (default 50)")
    p.add_argument("--seed", type=int, default=DEFAULT_SEED,
                   help=f"first trial seed (default {DEFAULT_SEED}; held out from the "
                   "demonstration seeds 0..n_demos-1)")
    p.add_argument("--workers", type=int, default=1, help="worker processes (default 1)")
    p.add_argument("--cluster", default=None,
                   help="address of a Dask scheduler (tcp://host:8786); overrides --workers")
    p.add_argument("--no-plots", action="store_true", help="no trajectory plots")
    p.add_argument("--quiet", action="store_true", help="no progress bar, no table")
    p.set_defaults(func=_cmd)
