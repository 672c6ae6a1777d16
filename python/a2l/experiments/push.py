"""The push experiment (thesis chapter 5).

``a2l experiment push`` runs the iterative framework (:mod:`a2l.framework`) on the push
effects and writes a run directory: ``config.json``, ``metrics.json``,
``dataset.parquet``, ``skills/push.a2lb`` (the final skill) and one bundle per iteration,
``score.png``, ``trajectories.png``, ``policy.png`` and ``report.md``
(:mod:`a2l.experiments.push_report`, whose names are re-exported here), and the held-out
misses with their causes, ``heldout_misses.csv`` and ``heldout_misses.png``
(:mod:`a2l.experiments.push_misses`). The discretization
study is :mod:`a2l.experiments.discretization`.
"""

from __future__ import annotations

import contextlib
import shutil
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import pandas as pd

from a2l.atomic import atomic_write_text
from a2l.experiments.push_misses import (
    miss_causes,
    miss_table,
    misses_markdown,
    plot_misses,
)
from a2l.experiments.push_report import (
    context_label,
    context_source,
    plot_policy,
    plot_scores,
    plot_trajectories,
    report_markdown,
    results_table,
    with_heldout,
)
from a2l.framework import FrameworkConfig, FrameworkResult, IterationResult, run_framework
from a2l.framework.presets import preset_of
from a2l.parallel import Executor
from a2l.progress import ProgressBars, print_tables
from a2l.rollout.env import ROBOT_SCENES
from a2l.rundir import command_line, make_run_dir, read_json, write_json
from a2l.seeds import mark_report, seed_record

__all__ = [
    "final_validation",
    "plot_policy",
    "plot_scores",
    "plot_trajectories",
    "record_validations",
    "results_table",
    "run_push_experiment",
    "with_heldout",
]

def _robot_entry(cfg: FrameworkConfig) -> dict[str, str] | None:
    """The bundle's record of the run's robot (:meth:`a2l.robot.RobotEntry.record`); None
    for the virtual scene."""
    if cfg.scene not in ROBOT_SCENES:
        return None
    from a2l.robot import robot_entry

    return robot_entry(cfg.robot).record()


def run_push_experiment(cfg: FrameworkConfig | None = None, out: str | Path | None = None,
                        workers: int = 1, cluster: str | None = None,
                        resume: str | Path | None = None, quiet: bool = False,
                        plots: bool = True, acquisition: str = "random",
                        noveb_evaluations: int = 200,
                        executor: Executor | None = None,
                        record: str | Path | None = None) -> dict[str, Any]:
    """Run (or resume) the push experiment and write its run directory.

    Parameters
    ----------
    cfg : FrameworkConfig, optional
        Parameters (ignored when resuming: the run's ``config.json`` is used).
    out : path, optional
        Run directory (default ``runs/push-<timestamp>``).
    workers : int
        Local worker processes for rollouts.
    cluster : str, optional
        Dask scheduler address; rollouts run there.
    resume : path, optional
        Run directory of an interrupted run to continue.
    quiet : bool
        No progress bar, no table.
    plots : bool
        Write the PNG plots.
    acquisition : {"random", "noveb"}
        Iteration 0's interactions: random babbling around the object (``docs/method.md``), or
        NovEB over the whole reachable table, told camera images only
        (:mod:`a2l.framework.noveb_rollouts`); ignored when resuming.
    noveb_evaluations : int
        NovEB's trajectories, with ``acquisition="noveb"``.
    executor : a2l.parallel.Executor, optional
        Where rollouts run, shared by several runs (a sweep): its worker processes are
        started once, not per run, and it stays open. When given, `workers` and `cluster`
        are ignored (the metrics record the executor's).
    record : path, optional
        Write the final validation's rollouts to this Rerun recording (``.rrd``; ``a2l
        view``): per rollout and step the end-effector, the object, the movement, the bins
        and the effect.

    Returns
    -------
    dict
        The content of ``metrics.json`` plus ``run_dir``.
    """
    if resume is not None:
        run_dir, cfg, acquisition, noveb_evaluations = _resumed(Path(resume),
                                                                noveb_evaluations)
    else:
        cfg = cfg or FrameworkConfig()
        run_dir = _new_run(cfg, out, acquisition, noveb_evaluations)
    t0 = time.perf_counter()
    noveb_log: dict[str, Any] = {}
    if executor is not None:
        workers, cluster = executor.workers, executor.cluster
    own = Executor(workers=workers, cluster=cluster) if executor is None else None
    with own or contextlib.nullcontext(), ProgressBars(quiet) as bars:
        first = _noveb_first(noveb_evaluations, noveb_log) if acquisition == "noveb" else None
        result = run_framework(cfg, run_dir, executor or own, progress=bars.update,
                               on_iteration=lambda m: _iteration_done(bars, m),
                               robot=_robot_entry(cfg), first_acquisition=first)
    final = run_dir / "skills" / "push.a2lb"
    shutil.copyfile(result.bundle, final)
    result.dataset.to_parquet(run_dir / "dataset.parquet", index=False)
    history = with_heldout(result.iterations, result.heldout, result.movements)
    miss_lines, table = None, None
    if result.heldout_score is not None:  # every held-out miss with its cause
        table = miss_table(cfg, result.heldout_validation, final)
        atomic_write_text(run_dir / "heldout_misses.csv", table.to_csv(index=False))
        miss_lines = misses_markdown(table, len(result.heldout_validation),
                                     figure=plots)
    metrics = {
        **_metrics(cfg, result, history, table, run_dir, final),
        "wall_s": time.perf_counter() - t0, "workers": workers, "cluster": cluster,
        **({"acquisition": {"method": acquisition, **noveb_log}}
           if acquisition != "random" else {}),
    }
    write_json(run_dir / "metrics.json", metrics)
    if record is not None:
        record_validations(record, {"": (result.validation, final)},
                           name="a2l experiment push")
    if plots:
        _plot_run(cfg, result, history, table, run_dir, final)
    atomic_write_text(run_dir / "report.md", mark_report(
        report_markdown(cfg, result, run_dir, history, miss_lines=miss_lines),
        seed_record("push", [cfg.seed])))
    if not quiet:
        print_tables(results_table(history))
        print(_summary_line(cfg, result, run_dir))
    return {**metrics, "run_dir": str(run_dir)}


def _resumed(run_dir: Path, noveb_evaluations: int
             ) -> tuple[Path, FrameworkConfig, str, int]:
    """An interrupted run's directory, configuration, acquisition and NovEB budget, read
    from its ``config.json``."""
    if not (run_dir / "config.json").is_file():
        raise FileNotFoundError(f"cannot resume: '{run_dir}/config.json' does not exist")
    saved = read_json(run_dir / "config.json")
    acq = saved.get("acquisition", {"method": "random"})
    return (run_dir, FrameworkConfig.from_dict(saved["framework"]), acq["method"],
            int(acq.get("evaluations", noveb_evaluations)))


def _new_run(cfg: FrameworkConfig, out: str | Path | None, acquisition: str,
             noveb_evaluations: int) -> Path:
    """Check the acquisition arguments, make the run directory and write its
    ``config.json`` (with the command that reruns it)."""
    if acquisition not in ("random", "noveb"):
        raise ValueError(f"acquisition: unknown {acquisition!r}; choose 'random' or "
                         "'noveb'")
    if noveb_evaluations < 1:
        raise ValueError(f"noveb_evaluations: must be >= 1, got {noveb_evaluations}")
    robot = _robot_entry(cfg)
    name = robot["name"] if cfg.scene == "bullet" and robot else cfg.scene
    run_dir = make_run_dir(f"push-{name}", out)
    write_json(run_dir / "config.json", {
        "experiment": "push", "framework": cfg.to_dict(),
        **({"acquisition": {"method": acquisition, "evaluations": noveb_evaluations}}
           if acquisition != "random" else {}),
        "command": command_line(
            ["a2l", "experiment", "push", "--out", run_dir]
            + (["--acquisition", acquisition, "--noveb-evaluations", noveb_evaluations]
               if acquisition != "random" else []), cfg),
        "seed_use": seed_record("push", [cfg.seed]),
    })
    return run_dir


def _metrics(cfg: FrameworkConfig, result: FrameworkResult, history: list[dict[str, Any]],
             table: pd.DataFrame | None, run_dir: Path, final: Path) -> dict[str, Any]:
    """The results part of ``metrics.json`` (the run's wall time, workers and acquisition
    are added by the caller)."""
    return {
        "experiment": "push", "scene": cfg.scene,
        **({"robot": robot["name"]} if (robot := _robot_entry(cfg)) else {}),
        "n_effects": cfg.discretization.n_effects,
        "seed": cfg.seed, "context_source": context_source(cfg),
        # the baseline's rows are told from the defaults' by this (absent: the defaults)
        **({"preset": preset} if (preset := preset_of(cfg.to_dict())) else {}),
        "iterations": history,
        "heldout_success": result.heldout_success,
        "heldout_success_rate": result.heldout_success_rate,
        "final_success": next(m.get("success") for m in reversed(history) if m["accepted"]),
        "final_score": result.final_score, "heldout_score": result.heldout_score,
        "heldout": {"starts": cfg.heldout.n_starts, "r_low": cfg.heldout.r_low,
                    "r_high": cfg.heldout.r_high},
        **({"heldout_miss_causes": miss_causes(table)} if table is not None else {}),
        "bundle": str(final.relative_to(run_dir)),
    }


def _plot_run(cfg: FrameworkConfig, result: FrameworkResult, history: list[dict[str, Any]],
              table: pd.DataFrame | None, run_dir: Path, final: Path) -> None:
    """``score.png``, ``trajectories.png``, ``policy.png`` and, with held-out starts,
    ``heldout_trajectories.png`` and ``heldout_misses.png``."""
    plot_scores(history, run_dir / "score.png")
    plot_trajectories(cfg, result.validation, run_dir / "trajectories.png")
    if result.heldout_score is not None:
        plot_trajectories(cfg, result.heldout_validation,
                          run_dir / "heldout_trajectories.png",
                          title="Held-out trajectories")
    plot_policy(cfg, final, run_dir / "policy.png")
    if table is not None and not table.empty:
        plot_misses(cfg, result.heldout_validation, table,
                    run_dir / "heldout_misses.png")


def _summary_line(cfg: FrameworkConfig, result: FrameworkResult, run_dir: Path) -> str:
    """The line printed after the results table: held-out success per effect, the final
    score, the context source and the run directory."""
    held, rate = result.heldout_score, result.heldout_success
    return ((f"held-out success {rate:.1%} ("
             + ", ".join(f"{e} {v:.0%}" for e, v in result.heldout_success_rate.items())
             + "); " if rate is not None else "")
            + f"final score {result.final_score:.1f}"
            + (f" (held-out {held:.1f})" if held is not None else "")
            + f"; context: {context_label(cfg)}"
            + f"; run directory: {run_dir}")


def final_validation(run_dir: str | Path, table: str = "validation"
                     ) -> tuple[pd.DataFrame, Path]:
    """A finished push run's final validation rollouts (its newest checkpoint's
    ``<table>.parquet``: ``"validation"`` or ``"heldout"``) and its final bundle."""
    from a2l.rundir import latest_checkpoint

    ck = latest_checkpoint(run_dir)
    if ck is None:
        raise FileNotFoundError(f"'{run_dir}' holds no checkpoint: not a finished push run")
    return ck[2][table], Path(run_dir) / "skills" / "push.a2lb"


def record_validations(path: str | Path, runs: Mapping[str, tuple[pd.DataFrame, Path]],
                       name: str) -> Path:
    """Push runs' validation rollouts as one Rerun recording (:mod:`a2l.rollout.recording`,
    ``a2l view``): per run (its group, e.g. ``seed/3``; ``""`` for one run alone), one
    rollout per row of its table (:func:`a2l.acquisition.interactions.rollouts_table`), its
    movements, bins and effect names read from its bundle.

    Parameters
    ----------
    path : path
        The ``.rrd`` file.
    runs : mapping of str to (DataFrame, Path)
        Group -> (the rollouts' table, the bundle that ran them).
    name : str
        The recording's application id (the command).

    Returns
    -------
    Path
        The recording written.
    """
    from a2l.rollout.recording import RerunRecorder, record_rollouts
    from a2l.skills.runner import CppSkillRunner

    rec = RerunRecorder(path, name=name)
    for group, (frame, bundle) in runs.items():
        record_rollouts(rec, list(frame.itertuples(index=False)),
                        CppSkillRunner(bundle).skill, group=group)
    return rec.close()


def _iteration_done(bars: ProgressBars, m: IterationResult) -> None:
    """Print iteration `m`'s line above the bars and clear them for the next iteration."""
    bars.print(f"iteration {m.iteration}: score {m.score:.1f} "
               f"({'accepted' if m.accepted else 'rejected'}), dataset {m.dataset_size} rows, "
               f"{m.wall_s:.1f} s")
    bars.clear()


def _noveb_first(evaluations: int, log: dict[str, Any]) -> Any:
    """Iteration 0 by NovEB (:func:`a2l.framework.noveb_rollouts.noveb_acquire`); what it
    did goes into `log` (evaluations, interactions kept, robot movements, archive)."""
    from a2l.acquisition.interactions import Interactions
    from a2l.framework.noveb_rollouts import noveb_acquire

    def first(cfg: FrameworkConfig, executor: Executor, _iteration: int, progress: Any
              ) -> Interactions:
        t = time.perf_counter()
        rollouts, noveb, movements = noveb_acquire(cfg, executor, evaluations,
                                                   progress=progress)
        log.update({"evaluations": evaluations, "interactions": len(rollouts),
                    "movements": movements, "archive_size": len(noveb.archive),
                    "wall_s": time.perf_counter() - t})
        return Interactions(rollouts, movements)

    return first
