"""Run a PDDL planner with a hard time limit: pyperplan (default) or Fast Downward.

Every search runs in a child process of its own (``python -m a2l.planning._child``, leading
a new process group) that is killed, with whatever it started, when the time limit is
reached: an unsolvable or timed-out problem always ends in a :class:`PlanResult` that
says so, never in a hang.

- ``pyperplan``: the pure-Python planner, called through its Python API in the child;
  A* with the LM-cut heuristic by default (optimal plans; complete, so an exhausted search
  proves that there is no plan).
- ``fast-downward``: through ``unified-planning`` + ``up-fast-downward`` (its wheel carries
  the compiled planner); ``OneshotPlanner(name="fast-downward")`` runs LAMA-first. An
  unsolvable task comes back as ``UNSOLVABLE_INCOMPLETELY`` (reported as ``unsolvable``).
  (``up-pyperplan`` is not used: it misreports unsolvable tasks.)
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from a2l.atomic import atomic_write_text
from a2l.errors import A2LFileNotFoundError, A2LValueError

__all__ = ["PLANNERS", "PlanResult", "PlanStep", "solve", "solve_files", "write_task"]

#: Planner names accepted by :func:`solve`.
PLANNERS = ("pyperplan", "fast-downward")


@dataclass(frozen=True)
class PlanStep:
    """One step of a plan: an operator (skill) name and its arguments."""

    name: str
    args: tuple[str, ...] = ()

    def __str__(self) -> str:
        return "(" + " ".join((self.name, *self.args)) + ")"


@dataclass(frozen=True)
class PlanResult:
    """What a planner call produced.

    Attributes
    ----------
    status : str
        ``solved``, ``unsolvable`` (the planner says no plan exists), ``timeout`` (stopped
        at the time limit) or ``error`` (bad PDDL, planner missing...).
    planner : str
        Which planner ran.
    plan : tuple of PlanStep
        The plan when solved (may be empty if the goal already holds), else empty.
    time_s : float
        Wall time of the call, child start-up included (s).
    message : str
        Why, when not solved.
    """

    status: str
    planner: str
    plan: tuple[PlanStep, ...] = ()
    time_s: float = 0.0
    message: str = ""

    @property
    def solved(self) -> bool:
        """True if a plan was found."""
        return self.status == "solved"

    def report(self) -> str:
        """A short human-readable report."""
        if self.solved:
            steps = "\n".join(f"  {i + 1}. {s}" for i, s in enumerate(self.plan))
            return (f"{self.planner}: plan of {len(self.plan)} steps in {self.time_s:.2f} s"
                    + (f"\n{steps}" if steps else " (the goal already holds)"))
        return f"{self.planner}: no plan ({self.status}) after {self.time_s:.2f} s: {self.message}"


def _kill(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        proc.kill()
    proc.communicate()


def solve_files(domain: str | os.PathLike[str], problem: str | os.PathLike[str],
                planner: str = "pyperplan", time_limit: float = 10.0,
                search: str = "astar", heuristic: str = "lmcut") -> PlanResult:
    """Solve a PDDL domain and problem file within `time_limit` seconds.

    Parameters
    ----------
    domain, problem : str or PathLike
        PDDL files.
    planner : {"pyperplan", "fast-downward"}
        Which planner.
    time_limit : float
        s, > 0: the call returns by then (plus the time to kill the child).
    search, heuristic : str
        pyperplan's search (``astar``, ``gbf``, ``wastar``, ``ehs``, ``bfs``...) and
        heuristic (``lmcut``, ``hff``, ``hadd``, ``hmax``, ``blind``...).

    Returns
    -------
    PlanResult
        Never raises for an unsolvable or slow problem; see its ``status``.

    Raises
    ------
    a2l.A2LValueError
        Unknown planner or non-positive time limit.
    a2l.A2LFileNotFoundError
        A file is missing.
    """
    if planner not in PLANNERS:
        raise A2LValueError(f"unknown planner {planner!r}; choose from {PLANNERS}")
    if not time_limit > 0:
        raise A2LValueError(f"time_limit must be > 0 s, got {time_limit}")
    for f in (domain, problem):
        if not Path(f).is_file():
            raise A2LFileNotFoundError(f"PDDL file '{f}' does not exist")
    t0 = time.perf_counter()
    args = {"planner": planner, "domain": str(domain), "problem": str(problem),
            "search": search, "heuristic": heuristic, "time_limit": time_limit}
    # a new session: the child leads its own process group, killed whole at the limit
    # (Fast Downward's own process included)
    proc = subprocess.Popen([sys.executable, "-m", "a2l.planning._child", json.dumps(args)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    out: tuple[str, Any] | None = None
    try:
        stdout, stderr = proc.communicate(timeout=max(time_limit - (time.perf_counter() - t0),
                                                      0.0))
        lines = stdout.strip().splitlines()
        try:
            answer = json.loads(lines[-1]) if lines else None
        except json.JSONDecodeError:
            answer = None
        if answer is None:
            out = ("error", f"the {planner} process ended without an answer (exit code "
                            f"{proc.returncode}): {stderr.strip()[-500:]}")
        else:
            out = (answer["status"], answer["payload"])
    except subprocess.TimeoutExpired:
        _kill(proc)
    elapsed = time.perf_counter() - t0
    if out is None:
        return PlanResult("timeout", planner, (), elapsed,
                          f"stopped at the time limit of {time_limit:g} s")
    status, payload = out
    if status == "solved":
        steps = tuple(PlanStep(n, tuple(a)) for n, a in payload)
        return PlanResult("solved", planner, steps, elapsed)
    return PlanResult(status, planner, (), elapsed, str(payload))


def write_task(out_dir: str | os.PathLike[str], domain: str, problem: str,
               name: str = "task") -> tuple[Path, Path]:
    """Write ``<name>-domain.pddl`` and ``<name>-problem.pddl`` into `out_dir` (atomically).

    Returns
    -------
    (Path, Path)
        The domain and problem files.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    return (atomic_write_text(out / f"{name}-domain.pddl", domain),
            atomic_write_text(out / f"{name}-problem.pddl", problem))


def solve(domain: str, problem: str, out_dir: str | os.PathLike[str], planner: str = "pyperplan",
          time_limit: float = 10.0, name: str = "task", **kwargs: str) -> PlanResult:
    """Write the domain and problem texts into `out_dir`, solve them, and write the result
    as ``<name>-plan-<planner>.txt`` (the plan, one step a line, or the report).

    Rerun from the shell with ``python -m a2l.planning DOMAIN PROBLEM --planner P``.
    """
    d, p = write_task(out_dir, domain, problem, name)
    res = solve_files(d, p, planner, time_limit, **kwargs)
    text = ("\n".join(str(s) for s in res.plan) + "\n") if res.solved else res.report() + "\n"
    atomic_write_text(Path(out_dir) / f"{name}-plan-{planner}.txt", text)
    return res
