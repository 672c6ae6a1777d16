"""A whole Baxter push run, end to end: where its time goes, and its wall time on 1 and 2
workers.

The run is ``a2l experiment push --scene baxter --effects 4 --seed 0`` with the demo's
budget (:data:`RUN`: 8 starts, 2 iterations, 32 held-out starts; the camera is the context
source). One instrumented run with 1 worker splits its time into the framework's phases
(acquire, extend, skill generation, validation, held-out validation, plots) and, across
them, into physics (PyBullet steps), rendering (PyBullet's software renderer), perception
(OpenCV on the frames), the waypoints' IK, the episodes' resets and skill learning; the
start-up (imports, in a fresh process) is measured apart. Bare runs with 1 and 2 workers
give the wall and CPU times, and whether their metrics equal the instrumented run's.

Standalone: ``python benchmarks/bench_framework_baxter.py [--max_iterations N] [--n_starts N]
[--heldout_starts N] [--workers 1 2]`` (the training and held-out start counts) prints the
same Markdown (a shorter run to try a change; the section in BENCHMARKS.md is the full one).
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from a2l.acquisition.interactions import Rollout
from a2l.experiments import push
from a2l.experiments.push import run_push_experiment
from a2l.framework import FrameworkConfig, loop
from a2l.framework.random_babbling import RandomBabbling
from a2l.framework.waypoints import EffectDirected
from a2l.parallel import Executor, Pending
from a2l.sim.bodies import BodyCache
from a2l.sim.bullet.motion import MotionMixin
from a2l.sim.perception import Camera, Perception

TITLE = "Iterative framework: a whole Baxter push run (where the time goes)"

#: The run: the demo's push part (``a2l demo``), seed 0.
RUN = {"scene": "baxter", "seed": 0, "max_iterations": 2, "discretization.n_effects": 4,
       "starts.n_starts": 8, "heldout.n_starts": 32}

#: Framework phases, timed where :func:`a2l.framework.run_framework` calls them.
PHASES = ("acquire", "extend", "generate_skill", "validate", "validate_heldout")
#: The plots of :func:`run_push_experiment`.
PLOTS = ("plot_scores", "plot_trajectories", "plot_policy")
#: What the phases' time is made of: (label, class, method).
PARTS = (("physics (PyBullet steps)", MotionMixin, "_sim_step"),
         ("rendering (PyBullet TinyRenderer)", Camera, "render"),
         ("perception (OpenCV on the frames)", Perception, "top_faces"),
         ("waypoints' IK (C++)", MotionMixin, "_plan_path"),
         ("episode resets (bodies rebuilt)", BodyCache, "rebuild"))


class _Patch:
    """Replaces attributes by timed wrappers, and puts them back."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {}
        self.calls: dict[str, int] = {}
        self._undo: list[tuple[Any, str, Any]] = []

    def time(self, label: str, owner: Any, name: str) -> None:
        fn = getattr(owner, name)
        self.seconds.setdefault(label, 0.0)
        self.calls.setdefault(label, 0)

        def timed(*args: Any, **kwargs: Any) -> Any:
            t = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                self.seconds[label] += time.perf_counter() - t
                self.calls[label] += 1

        self._undo.append((owner, name, fn))
        setattr(owner, name, timed)

    def wrap(self, owner: Any, name: str, make: Callable[[Any], Any]) -> None:
        fn = getattr(owner, name)
        self._undo.append((owner, name, fn))
        setattr(owner, name, make(fn))

    def undo(self) -> None:
        for owner, name, fn in reversed(self._undo):
            setattr(owner, name, fn)
        self._undo.clear()


@contextmanager
def breakdown() -> Iterator[_Patch]:
    """Time the phases, the plots and the :data:`PARTS` of a run in this process."""
    patch = _Patch()
    for name in PHASES:
        patch.time(name, loop, name)
    for name in PLOTS:
        patch.time("plots", push, name)
    for label, owner, name in PARTS:
        patch.time(label, owner, name)
    try:
        yield patch
    finally:
        patch.undo()


@contextmanager
def dropped() -> Iterator[dict[str, int]]:
    """Count the babbling tries sent to the workers, those given up before they ran
    (:meth:`a2l.parallel.Pending.drop`) and those told to their strategy: the rest ran and
    were dropped (asked ahead past a strategy's end,
    :func:`a2l.acquisition.protocol.drive_ahead`)."""
    count = {"sent": 0, "given_up": 0, "told": 0}
    patch = _Patch()

    def drop(fn: Any) -> Any:
        def wrapped(pending: Pending[Any], unwanted: Any) -> int:
            n = fn(pending, unwanted)
            count["given_up"] += n
            return n
        return wrapped

    def submit(fn: Any) -> Any:
        def wrapped(ex: Executor, task_fn: Any, tasks: Any, *a: Any, **k: Any) -> Any:
            tasks = list(tasks)
            if task_fn in (loop.babble_task, loop.directed_outcome_task):
                count["sent"] += len(tasks)
            return fn(ex, task_fn, tasks, *a, **k)
        return wrapped

    def tell(fn: Any) -> Any:
        def wrapped(s: Any, asked: Any, outcomes: list[Rollout]) -> Any:
            count["told"] += len(outcomes)
            return fn(s, asked, outcomes)
        return wrapped

    patch.wrap(Executor, "submit", submit)
    if hasattr(Pending, "drop"):  # (not in the code before it came)
        patch.wrap(Pending, "drop", drop)
    patch.wrap(RandomBabbling, "tell", tell)
    patch.wrap(EffectDirected, "tell", tell)
    try:
        yield count
    finally:
        patch.undo()


def _cpu() -> float:
    """CPU seconds of this process and its finished children (the worker processes)."""
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime


def _run(cfg: FrameworkConfig, workers: int, out: Path) -> tuple[dict[str, Any], float, float]:
    """One run: its metrics, wall and CPU seconds (workers' start-up included)."""
    t, c = time.perf_counter(), _cpu()
    m = run_push_experiment(cfg, out, workers=workers, quiet=True)
    return m, time.perf_counter() - t, _cpu() - c


def _same(a: dict[str, Any], b: dict[str, Any]) -> bool:
    """The two runs' metrics equal, wall times and where it ran aside."""
    def strip(m: dict[str, Any]) -> Any:
        its = [{k: v for k, v in it.items() if k not in ("wall_s", "heldout_wall_s")}
               for it in m["iterations"]]
        return its, {k: v for k, v in m.items()
                     if k not in ("iterations", "wall_s", "workers", "run_dir")}
    return strip(a) == strip(b)


def startup_s() -> dict[str, float]:
    """Wall seconds to import what a run needs, each in a fresh process: the command and
    the framework, and the skill-learning pipeline (pgmpy) it imports at its first skill."""
    out = {}
    for label, mod in (("a2l experiment push (CLI, framework, PyBullet scenes)",
                        "a2l.cli, a2l.experiments.push, a2l.sim.bullet"),
                       ("skill learning (pgmpy), at the first skill", "a2l.skills.pipeline")):
        code = (f"import time; t = time.perf_counter(); import {mod}; "
                "print(time.perf_counter() - t)")
        out[label] = float(subprocess.run([sys.executable, "-c", code], check=True,
                                          capture_output=True, text=True).stdout.split()[-1])
    return out


def report(run: dict[str, Any], workers: tuple[int, ...] = (1, 2)) -> str:
    """Measure `run` (a :class:`FrameworkConfig`'s fields by their dotted names) and return
    the Markdown."""
    cfg = FrameworkConfig().with_(run)
    with tempfile.TemporaryDirectory(prefix="a2l-bench-fwb-") as tmp:
        root = Path(tmp)
        load0 = os.getloadavg()[0]
        with breakdown() as b:
            mi, wall_i, cpu_i = _run(cfg, 1, root / "instrumented")
        bare = []
        for w in workers:
            load = os.getloadavg()[0]
            with dropped() as count:
                m, wall, cpu = _run(cfg, w, root / f"w{w}")
            bare.append((w, wall, cpu, load, dict(count), _same(m, mi)))
    start = startup_s()
    moves = mi["iterations"][-1]["robot_movements_total"]
    phases_s = sum(b.seconds[p] for p in PHASES)
    parts_s = sum(b.seconds[label] for label, _, _ in PARTS)
    learning = b.seconds["generate_skill"]
    rest = phases_s - parts_s - learning
    lines = [
        f"`a2l experiment push --scene baxter --effects {cfg.discretization.n_effects} "
        f"--seed {cfg.seed} --starts {cfg.starts.n_starts} --max_iterations "
        f"{cfg.max_iterations} --heldout.n_starts {cfg.heldout.n_starts}` (context from the "
        f"camera); {moves:,} discrete movements in "
        f"all (`robot_movements_total`), final score {mi['final_score']:.1f}, held-out "
        f"success {mi['heldout_success']:.1%}.",
        "",
        "Wall and CPU time of bare runs (CPU: the main process and its worker processes; the "
        "load is the machine's 1-minute load average as the run started: 2 cores, so above "
        "about 2 other jobs shared them):",
        "",
        "| workers | wall (s) | CPU (s) | load | babbling tries sent / given up / told | "
        "same metrics |",
        "|---|---|---|---|---|---|",
        *(f"| {w} | {wall:.1f} | {cpu:.1f} | {load:.1f} | {c['sent']:,} / "
          f"{c['given_up']:,} / {c['told']:,} | {same} |"
          for w, wall, cpu, load, c, same in bare),
        "",
        f"Where the time goes (an instrumented 1-worker run of its own, {wall_i:.1f} s wall, "
        f"{cpu_i:.1f} s CPU, load {load0:.1f} as it started):",
        "",
        "| phase | wall (s) | share |",
        "|---|---|---|",
        *(f"| `{p}` | {b.seconds[p]:.1f} | {b.seconds[p] / wall_i:.0%} |" for p in PHASES),
        f"| plots | {b.seconds['plots']:.1f} | {b.seconds['plots'] / wall_i:.0%} |",
        f"| the rest (run directory, bundles, report, workers' start) | "
        f"{wall_i - phases_s - b.seconds['plots']:.1f} | "
        f"{(wall_i - phases_s - b.seconds['plots']) / wall_i:.0%} |",
        "",
        "| across the phases | wall (s) | calls | share of the phases |",
        "|---|---|---|---|",
        *(f"| {label} | {b.seconds[label]:.1f} | {b.calls[label]:,} | "
          f"{b.seconds[label] / phases_s:.0%} |" for label, _, _ in PARTS),
        f"| skill learning (`generate_skill`) | {learning:.1f} | "
        f"{b.calls['generate_skill']:,} | {learning / phases_s:.0%} |",
        f"| the rest (the C++ skill step, closed loops, observations, Python) | {rest:.1f} "
        f"| | {rest / phases_s:.0%} |",
        "",
        "Start-up, each import in a fresh process (wall s): "
        + "; ".join(f"{k} {v:.1f}" for k, v in start.items()) + ".",
    ]
    return "\n".join(lines)


def run() -> str:
    return report(RUN)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    fields = {"n_starts": "starts.n_starts", "max_iterations": "max_iterations",
              "heldout_starts": "heldout.n_starts"}
    for name, path in fields.items():
        parser.add_argument(f"--{name}", type=int, default=RUN[path])
    parser.add_argument("--workers", type=int, nargs="*", default=[1, 2],
                        help="worker counts of the bare runs (none: only the breakdown)")
    args = parser.parse_args()
    run_cfg = {**RUN, **{path: getattr(args, k) for k, path in fields.items()}}
    print(report(run_cfg, tuple(args.workers)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
