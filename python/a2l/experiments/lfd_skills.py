"""``a2l experiment lfd-skills``: demonstrated skills learned, then tried on held-out seeds.

Each skill of :data:`a2l.lfd.library.SKILLS` is demonstrated by its scripted demonstrator
(demonstration seeds ``0 .. n_demos - 1``), learned with its configuration
(:func:`a2l.lfd.library.skill_config`: :data:`a2l.lfd.config.DEFAULT` for the push skills),
and run in closed loop through the C++ step from ``trials`` trial set-ups drawn from seeds
``seed, seed + 1, ...`` (default 1040: no demonstration and no tuning used them), in the
recipes' PyBullet scenes on a robot (scene ``bullet`` with ``robot``, Baxter by default: a
built-in name or a robot file; the objects stand at its work point and the bundles record
it), or in the C++ virtual scene (``virtual``: no robot). ``baxter``, the earlier name of
the PyBullet scenes on Baxter, is read as ``bullet`` on Baxter (:func:`resolve_scene`). Output:
``skills/<name>.a2lb``, ``trials.csv`` (one row per trial), ``metrics.json`` (success rate,
mean movements, failures by stop status, learning times) and ``report.md``.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from a2l.errors import A2LError, ConfigError
from a2l.lfd.config import LfDConfig
from a2l.progress import print_tables, progress_bar
from a2l.robot import DEFAULT_ROBOT
from a2l.seeds import experiment_seeds

__all__ = ["DEFAULT_SEED", "SCENES", "LfdTrial", "evaluate", "resolve_scene", "results_table",
           "scale_note", "run_lfd_skills", "trial_task"]

#: The scenes the trials run in: the PyBullet scenes of any robot, the C++ virtual scene (an
#: earlier name, :data:`a2l.rollout.env.LEGACY_SCENES`, is read by :func:`resolve_scene`).
SCENES = ("bullet", "virtual")
#: Where a trial reads the context, as reports name it.
CONTEXT_SOURCES = {"perceived": "camera", "ground_truth": "ground truth"}

#: Scenes per worker process, keyed by (skill, scene, config overrides).
_SCENES: dict[str, Any] = {}


def package_dir() -> str:
    """The directory of the a2l package this process imported."""
    import a2l

    return os.path.dirname(os.path.abspath(a2l.__file__))


def check_package(package: str) -> None:
    """Raise RuntimeError when this process (a worker) imported another copy of a2l than
    `package`, the parent's :func:`package_dir`: its results would not be the code under
    test's."""
    if package != package_dir():
        raise RuntimeError(f"this worker imported a2l from {package_dir()}, the parent from "
                           f"{package}: start the experiment with the interpreter of the "
                           "package under test")


#: First trial seed by default: the first evaluation seed of the registry (docs/seeds.md).
DEFAULT_SEED = experiment_seeds("lfd-skills").evaluation[0]


@dataclass(frozen=True)
class LfdTrial:
    """One trial of a learned skill, as a worker runs it (:func:`trial_task`).

    Attributes
    ----------
    skill : str
        The skill (:data:`a2l.lfd.library.SKILLS`).
    bundle : str
        Path of its learned bundle.
    seed : int
        Trial seed: the object's and the arm's start (:func:`a2l.lfd.library.reset_for_trial`).
    scene : {"bullet", "virtual"}
        The recipe's PyBullet scene on `robot`, or the C++ virtual scene.
    mode : {"table", "ds"}
        The context skill (the compiled table) or the DS alone.
    config : LfDConfig
        The skill's configuration (its ``step`` is the scene's movement length).
    package : str
        The a2l directory of the process that made the trial (default: this one's,
        :func:`package_dir`); a worker that imported another refuses to run it.
    context_source : {"perceived", "ground_truth"}
        Where the skill reads the context: the camera (default) or the simulator's truth.
    keep_run : bool
        The result then holds the :class:`a2l.rollout.run.SkillRun` as ``"run"``, to record.
    robot : str
        The robot of scene ``bullet`` (a built-in name or a robot file's path).
    """

    skill: str
    bundle: str
    seed: int
    scene: str
    mode: str
    config: LfDConfig
    package: str = field(default_factory=package_dir)
    context_source: str = "perceived"
    keep_run: bool = False
    robot: str = DEFAULT_ROBOT


def trial_task(task: LfdTrial) -> dict[str, Any]:
    """Run one trial: a row of ``trials.csv`` (plus ``"run"`` with ``task.keep_run``). A
    trial whose start the arm cannot reach with its gripper pointing down (a small arm, the
    PR2 above the block) is a failure of stop ``start_unreachable``, no movement made.

    Raises
    ------
    RuntimeError
        The worker imported another copy of a2l than the parent (``task.package``): its
        results would not be the code under test's.
    """
    from a2l.errors import UnreachableError
    from a2l.lfd.library import SKILLS, make_skill_scene, reset_for_trial
    from a2l.rollout.effect_tests import light_test
    from a2l.rollout.run import run_skill

    check_package(task.package)
    cfg = task.config
    name, scene_name = task.skill, task.scene
    source = task.context_source
    robot = task.robot if scene_name == "bullet" else None
    key = repr((name, scene_name, cfg.step, source, robot))
    scene = _SCENES.get(key)
    if scene is None:
        for old in _SCENES.values():
            old.close()
        _SCENES.clear()
        scene = _SCENES[key] = make_skill_scene(
            name, 0, cfg, scene=None if scene_name == "bullet" else scene_name,
            robot=robot, context_source=source)
    row = {"skill": name, "seed": task.seed, "scene": scene_name, "mode": task.mode,
           "context_source": source}
    try:
        reset_for_trial(scene, name, task.seed)
    except UnreachableError:
        return {**row, "success": False, "stop": "start_unreachable", "movements": 0,
                "produced_x": 0.0, "produced_y": 0.0, "wall": 0.0,
                **({"run": None} if task.keep_run else {})}
    recipe = SKILLS[name]
    by_light = recipe.extra.get("effect_by_light")
    run = run_skill(scene, task.bundle, recipe.effect, mode=task.mode,
                    object_name=recipe.object_name,
                    effect_test=light_test(by_light) if by_light else None)
    return {**row, "success": bool(run.success), "stop": run.stop, "movements": run.movements,
            "produced_x": float(run.produced[0]), "produced_y": float(run.produced[1]),
            "wall": run.wall, **({"run": run} if task.keep_run else {})}


def evaluate(bundles: dict[str, Path], seeds: Sequence[int], scene: str = "bullet",
             mode: str = "table", cfg: LfDConfig | None = None, executor: Any = None,
             on_done: Callable[[int], None] | None = None,
             context_source: str = "perceived", keep_runs: bool = False,
             robot: str = DEFAULT_ROBOT) -> list[dict[str, Any]]:
    """Run every skill of `bundles` from every trial seed; one result dict per trial.

    Parameters
    ----------
    bundles : dict of str to Path
        Skill name -> bundle.
    seeds : sequence of int
        Trial seeds.
    scene : {"bullet", "virtual"}
        The recipe's PyBullet scene on `robot`, or the C++ virtual scene.
    mode : {"table", "ds"}
    cfg : LfDConfig, optional
        Its ``step`` is the scenes' movement length (default: each skill's own,
        :func:`a2l.lfd.library.skill_config`).
    executor : a2l.parallel.Executor, optional
        Where trials run (default: this process).
    context_source : {"perceived", "ground_truth"}
        Where the skill reads the context: the camera (default) or the simulator's truth.
        Success is judged on the truth either way.
    keep_runs : bool
        Every result holds its run (``"run"``, :class:`a2l.rollout.run.SkillRun`), to record.
    robot : str
        The robot of scene ``bullet``.
    """
    from a2l.lfd.library import skill_config
    from a2l.parallel import Executor

    configs = {n: skill_config(n, cfg) for n in bundles}
    tasks = [LfdTrial(n, str(b), int(s), scene, mode, configs[n], package_dir(),
                      context_source, keep_runs, robot)
             for n, b in bundles.items() for s in seeds]
    if executor is None:
        with Executor(1) as ex:
            return ex.map(trial_task, tasks, on_done=on_done)
    return executor.map(trial_task, tasks, on_done=on_done)


def summarise(trials: pd.DataFrame) -> dict[str, dict[str, Any]]:
    """Per skill: ``success_rate``, ``successes``, ``trials``, ``mean_movements``,
    ``failures`` (stop status -> count) and the failing seeds."""
    out: dict[str, dict[str, Any]] = {}
    for name, g in trials.groupby("skill", sort=False):
        fails = g[~g.success]
        out[str(name)] = {
            "success_rate": float(g.success.mean()), "successes": int(g.success.sum()),
            "trials": len(g), "mean_movements": float(g.movements.mean()),
            "failures": {str(k): int(v) for k, v in fails.stop.value_counts().items()},
            "failed_seeds": [int(s) for s in fails.seed],
        }
    return out


def results_table(summary: dict[str, dict[str, Any]],
                  learning: dict[str, dict[str, Any]] | None = None) -> str:
    """Markdown table of :func:`summarise`'s `summary`: per skill the successes, mean
    movements, failures by stop status, failed seeds and (with `learning`, the
    ``metrics.json`` entry) the learning time."""
    lines = ["| skill | success | mean movements | failures (stop: count) | failed seeds |"
             + (" learning (s) |" if learning else ""),
             "|---|---|---|---|---|" + ("---|" if learning else "")]
    for name, s in summary.items():
        fails = ", ".join(f"{k}: {v}" for k, v in s["failures"].items()) or "-"
        lines.append(f"| {name} | {s['successes']}/{s['trials']} | "
                     f"{s['mean_movements']:.1f} | {fails} | "
                     f"{' '.join(map(str, s['failed_seeds'])) or '-'} |"
                     + (f" {learning[name]['seconds']:.2f} |" if learning else ""))
    return "\n".join(lines)


def learned_for(scene: str, robot: str) -> str | None:
    """The robot a skill tried in `scene` (:func:`resolve_scene`'s) is learned for: `robot`,
    or None in the virtual scene, which has none."""
    return None if scene == "virtual" else robot


def resolve_scene(scene: str | None, robot: str) -> str:
    """The scene of a run on `robot`: `scene`, ``"bullet"`` when None; an earlier scene name
    (:data:`a2l.rollout.env.LEGACY_SCENES`) is the scene it names now (``baxter``:
    ``"bullet"``, on Baxter only).

    Raises
    ------
    a2l.errors.ConfigError
        An unknown scene, another robot than its own with an earlier scene name, a robot
        other than the default in the virtual scene (which has none), an unknown robot or
        robot file.
    """
    from a2l.robot import robot_entry
    from a2l.rollout.env import LEGACY_SCENES, normalise_scene

    scene = "bullet" if scene is None else scene
    if scene not in (*SCENES, *LEGACY_SCENES):
        raise ConfigError("--scene", f"must be one of {list(SCENES)}, got {scene!r}")
    scene, robot = normalise_scene(scene, robot, "--robot")
    if scene == "virtual" and robot != DEFAULT_ROBOT:
        raise ConfigError("--robot", f"the virtual scene has no robot (asked for {robot!r}); "
                          "use scene 'bullet'")
    try:
        robot_entry(robot)
    except A2LError as exc:
        raise ConfigError("--robot", str(exc)) from None
    return scene


def run_lfd_skills(out: str | os.PathLike[str], skills: Sequence[str] | None = None,
                   trials: int = 20, seed: int = DEFAULT_SEED, scene: str | None = None,
                   mode: str = "table", workers: int = 1, cfg: LfDConfig | None = None,
                   quiet: bool = False, context_source: str = "perceived",
                   record: str | os.PathLike[str] | None = None,
                   robot: str = DEFAULT_ROBOT) -> dict[str, Any]:
    """Learn the skills and try them; write the run directory (see the module docstring).

    The skills are learned for `robot` (a built-in name or a robot file; their bundles
    record it) and tried in its PyBullet scenes (`scene` ``"bullet"``, the default), or
    learned for no robot and tried in the virtual scene (``"virtual"``); the scene
    ``baxter`` of earlier runs is ``"bullet"`` on Baxter (:func:`resolve_scene`).

    The trials read the context from `context_source`: the camera (``"perceived"``, the
    default) or the simulator's truth (``"ground_truth"``); the report names it. With
    `record`, every trial goes to a Rerun recording (``.rrd``): per skill (group ``<skill>``)
    one rollout per trial seed, its steps as :func:`a2l.rollout.recording.record_run` logs
    them, with a line saying the seed and how it ended.

    Returns
    -------
    dict
        The metrics written to ``metrics.json``.
    """
    from a2l.atomic import atomic_write_text
    from a2l.lfd.library import SKILLS, check_robot_for, learn_recipe, skill_config
    from a2l.parallel import Executor
    from a2l.rundir import command_line, make_run_dir, write_json
    from a2l.seeds import mark_report, seed_record

    names = list(skills or [n for n in SKILLS if n.startswith("push_")])
    unknown = [n for n in names if n not in SKILLS]
    if unknown:
        raise ConfigError("--skills", f"unknown skill(s) {unknown}; known: {sorted(SKILLS)}")
    scene = resolve_scene(scene, robot)
    for name in names if scene != "virtual" else ():
        try:
            check_robot_for(name, robot)
        except A2LError as exc:
            raise ConfigError("--skills", str(exc)) from None
    if context_source not in CONTEXT_SOURCES:
        raise ConfigError("--context_source", f"must be one of {list(CONTEXT_SOURCES)}, got "
                          f"{context_source!r}")
    run_dir = make_run_dir("lfd-skills", out)
    words = ["a2l", "experiment", "lfd-skills", "--out", run_dir, "--skills", ",".join(names),
             "--trials", trials, "--seed", seed, "--scene", scene, "--mode", mode,
             "--context_source", context_source, "--workers", workers,
             *(["--robot", robot] if scene == "bullet" else [])]
    learned_robot = learned_for(scene, robot)
    write_json(run_dir / "config.json", {
        "experiment": "lfd-skills", "skills": names, "trials": trials, "seed": seed,
        "scene": scene, "robot": learned_robot, "mode": mode, "context_source": context_source,
        "workers": workers,
        "configs": {n: skill_config(n, cfg).to_json() for n in names},
        "command": command_line(words, cfg, prefix="lfd."),
        "seed_use": seed_record("lfd-skills", range(seed, seed + trials))})
    bundles, learning = {}, {}
    for name in names:
        t0 = time.perf_counter()
        learned = learn_recipe(name, run_dir / "skills", cfg, robot=learned_robot)
        bundles[name] = learned.bundle
        learning[name] = {"rows": learned.rows, "seconds": time.perf_counter() - t0,
                          **{f"{k}_s": v for k, v in learned.timings.items()}}
    seeds = list(range(seed, seed + trials))
    with Executor(workers) as ex, progress_bar("trials", len(names) * trials, quiet) as bar:
        results = evaluate(bundles, seeds, scene, mode, cfg, ex, bar, context_source,
                           keep_runs=record is not None, robot=robot)
    if record is not None:
        _record(record, results, bundles)
    frame = pd.DataFrame(results)
    atomic_write_text(run_dir / "trials.csv", frame.to_csv(index=False))
    summary = summarise(frame)
    metrics = {"scene": scene, "robot": learned_robot, "mode": mode,
               "context_source": context_source,
               "seeds": [seeds[0], seeds[-1]],
               "config": skill_config(names[0], cfg).to_json(),
               "configs": {n: skill_config(n, cfg).to_json() for n in names},
               "skills": summary, "learning": learning}
    write_json(run_dir / "metrics.json", metrics)
    where = f"bullet, robot {robot}" if scene == "bullet" else scene
    lines = [f"# Demonstrated skills on held-out seeds ({where}, {mode}, context: "
             f"{CONTEXT_SOURCES[context_source]})", "",
             f"Trial seeds {seeds[0]}-{seeds[-1]}; demonstrations from seeds 0-"
             f"{skill_config(names[0], cfg).n_demos - 1}; config "
             f"{ {n: skill_config(n, cfg).to_json() for n in names} }.", "",
             *scale_note(scene, robot), results_table(summary, learning)]
    atomic_write_text(run_dir / "report.md", mark_report(
        "\n".join(lines) + "\n", seed_record("lfd-skills", seeds)))
    if not quiet:
        print(f"context: {CONTEXT_SOURCES[context_source]}")
        print_tables(lines[-1])
        print(f"results in {run_dir}/ (report.md, metrics.json, trials.csv, skills/)")
    return metrics


def scale_note(scene: str, robot: str) -> list[str]:
    """The report's note on a robot whose scene is scaled (a small arm,
    :func:`a2l.robot.table_layout`): the demonstrations are not."""
    if scene != "bullet":
        return []
    from a2l.robot import robot_entry, table_layout

    scale = table_layout(robot_entry(robot)).scale
    if scale >= 1.0:
        return []
    return [f"Robot {robot}'s scene is scaled by {scale:.2f} (objects, work point, "
            "movement): the demonstrations, their starts and the LfD configuration are not; "
            "a start out of the arm's reach is a failure of stop start_unreachable.", ""]


def record_trials(recorder: Any, trials: Sequence[dict[str, Any]], skill: Any,
                  object_name: str, group: str) -> int:
    """Log trials of :func:`trial_task` run with ``keep_run`` (their ``"run"`` is taken
    out) to `recorder` (:class:`a2l.rollout.recording.RerunRecorder`): one rollout each
    under `group`, its steps as :func:`a2l.rollout.recording.record_run` logs them
    (`skill`: the bundle's :class:`a2l._core.Skill`), and a line with the seed and how it
    ended. Returns the number of trials logged."""
    from a2l.rollout.recording import record_run

    for i, r in enumerate(trials):
        run = r.pop("run")
        if run is not None:  # None: the start was out of reach, nothing ran
            record_run(recorder, run, skill, object_name=object_name, rollout=i, group=group)
        recorder.note(f"{r['skill']} seed {r['seed']}: "
                      f"{'success' if r['success'] else 'failure'} ({r['stop']})")
    return len(trials)


def _record(path: str | os.PathLike[str], results: list[dict[str, Any]],
            bundles: dict[str, Path]) -> None:
    """The trials' runs (taken out of `results`) as a Rerun recording: group ``<skill>``,
    one rollout per trial in seed order."""
    from a2l.lfd.library import SKILLS
    from a2l.rollout.recording import RerunRecorder
    from a2l.skills.runner import CppSkillRunner

    rec = RerunRecorder(path, name="a2l experiment lfd-skills")
    for name, bundle in bundles.items():
        record_trials(rec, [r for r in results if r["skill"] == name],
                      CppSkillRunner(bundle).skill, SKILLS[name].object_name, group=name)
    rec.close()
