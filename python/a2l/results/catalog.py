"""The named set of experiments behind the published tables, in two profiles.

Each :class:`Entry` is one table: the ``a2l`` commands that make its runs (per profile, on
evaluation seeds: ``docs/seeds.md``), the experiment's own table function that turns the
runs' ``metrics.json`` into Markdown (each experiment's report module is the one home of its
table), and the figures worth copying. ``quick`` runs fewer seeds and trials (about half an
hour on an idle 2-core machine); ``full`` runs what the experiments' pages describe (hours).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from a2l.rundir import read_json

__all__ = ["ENTRIES", "PROFILES", "Entry", "Run", "entries"]

#: The profiles: ``quick`` (fewer seeds and trials) and ``full``.
PROFILES = ("quick", "full")

#: The demonstrated skills every LfD table covers.
LFD_SKILLS = "push_right,push_left,push_close,push_far,grasp,press,grasp_light"


@dataclass(frozen=True)
class Run:
    """One command of an entry.

    Parameters
    ----------
    key : str
        The run directory's name, ``<out>/<entry>/<key>``.
    args : tuple of str
        The ``a2l`` arguments but ``--out`` and ``--workers`` (which the runner adds).
    resume : bool
        The command continues an interrupted run with ``--resume DIR`` (the push
        experiment) instead of being started again with ``--out DIR``.
    """

    key: str
    args: tuple[str, ...]
    resume: bool = False


@dataclass(frozen=True)
class Entry:
    """One published table.

    Parameters
    ----------
    name : str
        The table's name: ``docs/results/<name>.md`` and the README's
        ``<!-- results:<name> -->`` block.
    title : str
        What the table shows (its page's title).
    runs : dict of str to list of Run
        Per profile, the runs to make.
    table : callable
        ``table(metrics)``: the Markdown table of the runs' ``metrics.json`` (in run order).
    figures : tuple of str
        Figures to copy from the first run directory (paths inside it), when they exist.
    """

    name: str
    title: str
    runs: dict[str, list[Run]]
    table: Callable[[list[dict[str, Any]]], str]
    figures: tuple[str, ...] = field(default=())

    def tabulate(self, run_dirs: Sequence[Path]) -> str:
        """The table of the finished runs in `run_dirs`."""
        return self.table([read_json(Path(d) / "metrics.json") for d in run_dirs])


def _push_virtual(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.sweep import headline_table

    return headline_table(ms[0])


def _push_baxter(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.push_report import headline_table

    return headline_table(ms)


def _babbling(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.babbling_plots import summary_table

    return summary_table({k: [{"totals": t} for t in v] for k, v in ms[0]["runs"].items()})


def _lasa(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.lasa_report import headline_table

    return headline_table(ms[0])


def _lfd(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.lfd_skills import results_table

    return results_table(ms[0]["skills"])


def _perturbations(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.perturbation_report import condition_table

    return condition_table(ms[0]["skills"])


def _tasks(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.tasks_report import results_table

    return results_table(ms[0]["tasks"])


def _push(key: str, seed: int, effects: int, *extra: str) -> Run:
    return Run(key, ("experiment", "push", "--scene", "baxter", "--n_effects", str(effects),
                     "--seed", str(seed), "--quiet", *extra), resume=True)


#: Every table, in the order of the README.
ENTRIES: tuple[Entry, ...] = (
    Entry("push-virtual", "The push experiment in the virtual scene: iterations to score 100 "
          "per seed (a2l experiment sweep)",
          {"quick": [Run("sweep", ("experiment", "sweep", "--scene", "virtual", "--n_effects",
                                   "4", "--seeds", "1000-1009", "--quiet"))],
           "full": [Run("sweep", ("experiment", "sweep", "--scene", "virtual", "--n_effects",
                                  "4", "--seeds", "1000-1029", "--quiet"))]},
          _push_virtual),
    Entry("push-baxter", "The push experiment on Baxter in PyBullet (a2l experiment push)",
          {"quick": [_push("s1000-e4", 1000, 4, "--max_iterations", "3")],
           "full": [_push("s1000-e4", 1000, 4), _push("s1001-e4", 1001, 4),
                    _push("s1002-e4", 1002, 4), _push("s1000-e8", 1000, 8)]},
          _push_baxter, ("trajectories.png", "heldout_trajectories.png")),
    Entry("babbling", "Exploration: NovEB against random motor and random goal babbling "
          "(a2l experiment babbling-compare)",
          {"quick": [Run("compare", ("experiment", "babbling-compare", "--scene", "push",
                                     "--evaluations", "100", "--seeds", "1", "--first-seed",
                                     "1000", "--quiet"))],
           "full": [Run("compare", ("experiment", "babbling-compare", "--scene", "push",
                                    "--evaluations", "2000", "--seeds", "5", "--first-seed",
                                    "1000", "--quiet"))]},
          _babbling, ("progress.png",)),
    Entry("lasa", "The diffeomorphic DS on the LASA handwriting set (a2l experiment lasa)",
          {"quick": [Run("lasa", ("experiment", "lasa", "--starts", "1000", "--seed", "1000",
                                  "--quiet"))],
           "full": [Run("lasa", ("experiment", "lasa", "--seed", "1000", "--quiet"))]},
          _lasa, ("lasa.png",)),
    Entry("lfd-skills", "Skills learned from demonstrations, on held-out trial seeds "
          "(a2l experiment lfd-skills)",
          {"quick": [Run("lfd", ("experiment", "lfd-skills", "--skills", LFD_SKILLS,
                                 "--trials", "10", "--seed", "1000", "--quiet"))],
           "full": [Run("lfd", ("experiment", "lfd-skills", "--skills", LFD_SKILLS,
                                "--trials", "40", "--seed", "1000", "--quiet"))]},
          _lfd),
    Entry("perturbations", "Demonstrated skills under perturbations: success of the "
          "context skill / of the DS alone (a2l experiment perturbations)",
          {"quick": [Run("perturb", ("experiment", "perturbations", "--trials", "8",
                                     "--seed", "5000", "--quiet"))],
           "full": [Run("perturb", ("experiment", "perturbations", "--trials", "50",
                                    "--seed", "5000", "--quiet"))]},
          _perturbations, ("plots/push_left_none.png",)),
    Entry("tasks", "Planned tasks with the learned skills, with and without a fault "
          "(a2l experiment tasks)",
          {"quick": [Run("tasks", ("experiment", "tasks", "--trials", "4", "--seed", "7000",
                                   "--quiet"))],
           "full": [Run("tasks", ("experiment", "tasks", "--trials", "30", "--seed", "7000",
                                  "--quiet"))]},
          _tasks, ("tasks.png",)),
)


def entries(only: Sequence[str] | None = None) -> list[Entry]:
    """The entries named in `only` (all when None), in :data:`ENTRIES`' order.

    Raises
    ------
    KeyError
        A name that is no entry (the message lists the known ones).
    """
    known = {e.name: e for e in ENTRIES}
    if only is None:
        return list(ENTRIES)
    unknown = [n for n in only if n not in known]
    if unknown:
        raise KeyError(f"unknown results table(s) {unknown}; known: {', '.join(known)}")
    return [e for e in ENTRIES if e.name in set(only)]
