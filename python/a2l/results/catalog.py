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

from a2l.robot import DEFAULT_ROBOT
from a2l.rundir import read_json

__all__ = ["CONTEXTS", "ENTRIES", "PROFILES", "Entry", "Run", "by_context", "entries"]

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
        Per profile, the runs to make (none: the table is not part of that profile, e.g. a
        run of hours has no quick form).
    table : callable
        ``table(metrics)``: the Markdown table of the runs' ``metrics.json`` (in run order).
    figures : tuple of str
        Figures to copy from the first run directory (paths inside it), when they exist.
    metrics : str
        The file of each run directory the table reads (``metrics.json``; the demo writes
        its own numbers to ``demo.json``).
    evaluation : bool
        The table reports results, on evaluation seeds only (every entry but the demo, which
        shows what ``make demo`` prints on its own seed and says that this is a tuning seed).
    details : callable, optional
        ``details(run_dirs, fig_dir)``: Markdown lines for the page below its runs (not the
        README's block), e.g. each run's misses; it may copy figures into `fig_dir` and link
        them as ``<name>/<file>``.
    """

    name: str
    title: str
    runs: dict[str, list[Run]]
    table: Callable[[list[dict[str, Any]]], str]
    figures: tuple[str, ...] = field(default=())
    metrics: str = "metrics.json"
    evaluation: bool = True
    details: Callable[[Sequence[Path], Path], list[str]] | None = None

    def tabulate(self, run_dirs: Sequence[Path]) -> str:
        """The table of the finished runs in `run_dirs`."""
        return self.table([read_json(Path(d) / self.metrics) for d in run_dirs])


def _demo(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.demo_report import summary_table

    return summary_table(ms[0])


def _push_virtual(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.sweep import headline_table

    if len(ms) == 1:
        return headline_table(ms[0])
    return side_by_side("configuration", [_configuration(m) for m in ms],
                        [headline_table(m) for m in ms])


def _configuration(metrics: dict[str, Any]) -> str:
    """The name a table gives a run by the preset its metrics name (absent: the defaults)."""
    preset = metrics.get("preset")
    return f"`--preset {preset}`" if preset else "defaults"


def _push_baxter(ms: list[dict[str, Any]]) -> str:
    """The defaults' runs by context source (:data:`CONTEXTS`), then the baseline's (a
    preset's) runs, each group labelled in the leading column."""
    from a2l.experiments.push_report import headline_table

    sources = {"perceived": CONTEXTS[0], "ground_truth": CONTEXTS[1]}  # as metrics name them
    groups: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for m in ms:
        # runs before the metrics named their source read the camera (the default)
        key = (m.get("preset") or "", m.get("context_source", "perceived"))
        groups.setdefault(key, []).append(m)
    order = sorted(groups, key=lambda k: (k[0], list(sources).index(k[1])))
    labels = [sources[s] + (f", `--preset {p}`" if p else "") for p, s in order]
    return side_by_side("context", labels, [headline_table(groups[k]) for k in order])


def _push_baxter_misses(run_dirs: Sequence[Path], fig_dir: Path) -> list[str]:
    from a2l.experiments.push_misses import run_misses_markdown

    return run_misses_markdown(run_dirs, fig_dir)


def _babbling(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.babbling_plots import summary_table

    return summary_table({k: [{"totals": t} for t in v] for k, v in ms[0]["runs"].items()})


def _lasa(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.lasa_report import headline_table

    return headline_table(ms[0])


#: The context sources of the side-by-side tables, in run order: the camera (the default)
#: and the simulator's ground truth.
CONTEXTS = ("camera", "ground truth")


def by_context(tables: Sequence[str]) -> str:
    """One Markdown table of the same table made per context source (:data:`CONTEXTS`, in
    order): a leading ``context`` column names the source of each row
    (:func:`side_by_side`)."""
    return side_by_side("context", CONTEXTS, tables)


def side_by_side(column: str, labels: Sequence[str], tables: Sequence[str]) -> str:
    """One Markdown table of the same table made once per label: a leading `column` names
    the label of each row.

    Raises
    ------
    ValueError
        The tables' headers differ, or there are not as many as `labels`.
    """
    if len(tables) != len(labels):
        raise ValueError(f"expected {len(labels)} tables (one per {column}), got "
                         f"{len(tables)}")
    split = [t.strip().splitlines() for t in tables]
    if any(rows[:2] != split[0][:2] for rows in split):
        raise ValueError(f"the per-{column} tables have different headers")
    out = [f"| {column} " + split[0][0], "|---" + split[0][1]]
    for name, rows in zip(labels, split, strict=True):
        out += [f"| {name} {row}" for row in rows[2:]]
    return "\n".join(out)


def _lfd(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.lfd_skills import results_table

    return by_context([results_table(m["skills"]) for m in ms])


def _lfd_robots(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.lfd_skills import results_table

    return side_by_side("robot", [m.get("robot") or "none" for m in ms],
                        [results_table(m["skills"]) for m in ms])


def _perturbations(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.perturbation_report import condition_table

    return by_context([condition_table(m["skills"]) for m in ms])


def _tasks(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.tasks_report import results_table

    return by_context([results_table(m["tasks"]) for m in ms])


def _both(key: str, *args: str, resume: bool = False) -> list[Run]:
    """`args` run with the camera (the default) and with the ground truth (:data:`CONTEXTS`'
    order); `resume`: see :class:`Run`."""
    return [Run(key, args, resume),
            Run(f"{key}-gt", (*args, "--context_source", "ground_truth"), resume)]


#: The full profile's Baxter push runs: (key, seed, effects), each run with the defaults
#: (camera and ground truth) and with ``--preset thesis`` (camera).
BAXTER_PUSH_RUNS: tuple[tuple[str, int, int], ...] = (
    ("s1010-e4", 1010, 4), ("s1011-e4", 1011, 4), ("s1012-e4", 1012, 4), ("s1010-e8", 1010, 8))


def _push(key: str, seed: int, effects: int, *extra: str) -> list[Run]:
    """The Baxter push run of `seed` with the camera and with the ground truth (the runs of
    scene ``baxter``, its earlier name, are the same)."""
    return _both(key, "experiment", "push", "--scene", "bullet", "--robot", DEFAULT_ROBOT,
                 "--discretization.n_effects",
                 str(effects), "--seed", str(seed), "--quiet", *extra, resume=True)


def _thesis(key: str, seed: int, effects: int) -> Run:
    """The camera run of :func:`_push` with ``--preset thesis``, the baseline of the table."""
    cam, _ = _push(key, seed, effects)
    return Run(f"{key}-thesis", (*cam.args[:2], "--preset", "thesis", *cam.args[2:]), True)


def _push_on(robot: str, seed: int, *extra: str) -> Run:
    """The 4-effect push run of `seed` on `robot` (a built-in name or a robot file of the
    repository), with the camera."""
    key = f"{Path(robot).stem}-s{seed}"
    return Run(key, ("experiment", "push", "--scene", "bullet", "--robot", robot,
                     "--discretization.n_effects", "4", "--seed", str(seed), "--quiet",
                     *extra), True)


def _push_robots(ms: list[dict[str, Any]]) -> str:
    from a2l.experiments.push_report import headline_table

    return headline_table(ms)


#: The robot file of an arm that is not built in (docs/robots.md's worked example).
XARM_FILE = "examples/robots/xarm7.yaml"

#: The LfD skills the robots' table compares (a push each way, the grasp, the press).
ROBOT_LFD_SKILLS = "push_far,push_right,grasp,press"


def _lfd_on(robot: str, trials: int) -> Run:
    """The LfD skills of :data:`ROBOT_LFD_SKILLS` on `robot`, `trials` trials (camera)."""
    return Run(f"lfd-{robot}", ("experiment", "lfd-skills", "--robot", robot, "--skills",
                                ROBOT_LFD_SKILLS, "--trials", str(trials), "--seed", "1040",
                                "--quiet"))


def _babbling_on(robot: str, evaluations: int, seeds: int) -> Run:
    """NovEB and random motor babbling on `robot`, `seeds` seeds from 1000."""
    return Run(f"compare-{robot}", ("experiment", "babbling-compare", "--scene", "push",
                                    "--robot", robot, "--methods", "noveb", "random",
                                    "--evaluations", str(evaluations), "--seeds", str(seeds),
                                    "--first-seed", "1000", "--quiet"))

#: Every table, in the order of the README.
ENTRIES: tuple[Entry, ...] = (
    # what `make demo` runs after its set-up, on the demo's own seed (a tuning seed: the
    # demo shows the pipeline; the tables below are the evaluations)
    Entry("demo", "The main job: a2l demo (what make demo prints after its set-up)",
          {p: [Run("demo", ("demo", "--seed", "0"))] for p in PROFILES},
          _demo, ("trajectories.png",), metrics="demo.json", evaluation=False),
    Entry("push-virtual", "The push experiment in the virtual scene: iterations to score 100 "
          "per seed (a2l experiment sweep)",
          {"quick": [Run("sweep", ("experiment", "sweep", "--scene", "virtual",
                                   "--discretization.n_effects", "4", "--seeds", "1010-1019",
                                   "--quiet"))],
           "full": [Run("sweep", ("experiment", "sweep", "--scene", "virtual",
                                  "--discretization.n_effects", "4", "--seeds", "1010-1039",
                                  "--quiet")),
                    # the thesis' loop and representation beside the defaults, the same seeds
                    Run("sweep-thesis", ("experiment", "sweep", "--preset", "thesis",
                                         "--scene", "virtual", "--discretization.n_effects",
                                         "4", "--seeds", "1010-1039", "--quiet"))]},
          _push_virtual),
    Entry("push-baxter", "The push experiment on Baxter in PyBullet (a2l experiment push)",
          {"quick": _push("s1010-e4", 1010, 4, "--max_iterations", "3"),
           "full": [*(r for run in BAXTER_PUSH_RUNS for r in _push(*run)),
                    # the thesis' loop and representation beside them, with the camera
                    *(_thesis(*run) for run in BAXTER_PUSH_RUNS)]},
          _push_baxter, ("trajectories.png", "heldout_trajectories.png"),
          details=_push_baxter_misses),
    Entry("robots", "The push experiment on every built-in robot and on an arm from a robot "
          "file (a2l experiment push --scene bullet --robot; camera context)",
          {"quick": [_push_on("panda", 1010, "--max_iterations", "3")],
           "full": [_push_on("panda", 1010), _push_on("panda", 1011), _push_on("ur5", 1010),
                    _push_on("so101", 1010), _push_on(XARM_FILE, 1010)]},
          _push_robots, ("trajectories.png", "heldout_trajectories.png"),
          details=_push_baxter_misses),
    # the PR2's push run on its own: its loop runs all 10 iterations at 15-20 minutes each on
    # a 2-core machine (the five runs above: about 70 minutes together)
    Entry("robots-pr2", "The push experiment on the PR2 (a2l experiment push --scene bullet "
          "--robot pr2; camera context)",
          {"quick": [], "full": [_push_on("pr2", 1010)]},
          _push_robots, ("trajectories.png", "heldout_trajectories.png"),
          details=_push_baxter_misses),
    Entry("robots-lfd", "Skills learned from demonstrations on the Panda beside Baxter "
          "(a2l experiment lfd-skills --robot; camera context)",
          {"quick": [_lfd_on(DEFAULT_ROBOT, 10), _lfd_on("panda", 10)],
           "full": [_lfd_on(DEFAULT_ROBOT, 40), _lfd_on("panda", 40)]},
          _lfd_robots),
    # the PR2 (the robot of the thesis' NovEB chapter) plays an evaluation in ~1.1 s, twice
    # Baxter's: the full profile runs 400 evaluations (Baxter's table: 2000) on 2 seeds
    Entry("robots-babbling", "Exploration on the PR2: NovEB against random motor babbling "
          "(a2l experiment babbling-compare --robot pr2)",
          {"quick": [_babbling_on("pr2", 200, 2)], "full": [_babbling_on("pr2", 400, 2)]},
          _babbling, ("progress.png", "visits.png")),
    Entry("babbling", "Exploration: NovEB against random motor and random goal babbling "
          "(a2l experiment babbling-compare)",
          {"quick": [Run("compare", ("experiment", "babbling-compare", "--scene", "push",
                                     "--evaluations", "400", "--seeds", "2", "--first-seed",
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
          {"quick": _both("lfd", "experiment", "lfd-skills", "--skills", LFD_SKILLS,
                          "--trials", "10", "--seed", "1040", "--quiet"),
           "full": _both("lfd", "experiment", "lfd-skills", "--skills", LFD_SKILLS,
                         "--trials", "40", "--seed", "1040", "--quiet")},
          _lfd),
    Entry("perturbations", "Demonstrated skills under perturbations: success of the "
          "context skill / of the DS alone (a2l experiment perturbations)",
          {"quick": _both("perturb", "experiment", "perturbations", "--trials", "8",
                          "--seed", "5000", "--quiet"),
           "full": _both("perturb", "experiment", "perturbations", "--trials", "50",
                         "--seed", "5000", "--quiet")},
          _perturbations, ("plots/push_left_none.png",)),
    Entry("tasks", "Planned tasks with the learned skills, with and without a fault "
          "(a2l experiment tasks)",
          {"quick": _both("tasks", "experiment", "tasks", "--trials", "4", "--seed", "7000",
                          "--quiet"),
           "full": _both("tasks", "experiment", "tasks", "--trials", "30", "--seed", "7000",
                         "--quiet")},
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
