"""Run a PDDL planner with a hard time limit: pyperplan (default) or Fast Downward.

Every search runs in a planner worker (:class:`PlannerWorker`: ``python
a2l/planning/_worker.py``, leading a new process group) that stays alive between calls, so a
call pays no process start-up or import; a call past its time limit kills the worker, with
whatever it started, and the next call starts a new one: an unsolvable or timed-out problem
always ends in a :class:`PlanResult` that says so, never in a hang.

- ``pyperplan``: the pure-Python planner, called through its Python API in the worker;
  A* with the LM-cut heuristic by default (optimal plans; complete, so an exhausted search
  proves that there is no plan). It has no time limit of its own: the kill is the limit.
- ``fast-downward``: the planner shipped by ``up-fast-downward`` (its wheel carries the
  compiled search), without unified-planning: its translator runs in the worker, then the
  ``downward`` binary with the ``lama-first`` search options (what unified-planning's
  ``OneshotPlanner(name="fast-downward")`` runs). A task it finds unsolvable is reported as
  ``unsolvable``. (``up-pyperplan`` is not used: it misreports unsolvable tasks.)
"""

from __future__ import annotations

import atexit
import contextlib
import json
import os
import select
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from a2l.atomic import atomic_write_text
from a2l.errors import A2LFileNotFoundError, A2LValueError

__all__ = ["PLANNERS", "WORKER", "PlanResult", "PlanStep", "PlannerWorker", "solve",
           "solve_files", "write_task"]

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
        Wall time of the call (s): sending the task to the worker, the search, reading
        the plan; the worker's start-up when this call started it.
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


#: The worker's script, run by path: it imports neither a2l nor numpy (start-up ~0.3 s).
_WORKER_SCRIPT = Path(__file__).with_name("_worker.py")


class PlannerWorker:
    """A planner process that stays alive between calls (``python .../_worker.py``),
    started on the first call and after a kill.

    Each call writes one request line and reads one answer line; a call past its time
    limit kills the worker's process group (the worker and a running Fast Downward
    search) and the next call starts a new worker. A worker belongs to the process that
    started it: after a fork the child starts its own. Calls from several threads are
    served one at a time.
    """

    #: s allowed for a worker to start (import its planners) and say it is ready: not
    #: counted in a call's time limit.
    START_TIMEOUT = 120.0

    def __init__(self) -> None:
        self._proc: subprocess.Popen | None = None
        self._owner = 0
        self._buf = b""
        self._eof = False
        self._stderr: Any = None
        self._lock = threading.Lock()
        #: how many workers this object started (the first, and one per kill or crash)
        self.starts = 0

    @property
    def pid(self) -> int | None:
        """The running worker's process id (None if none runs)."""
        return self._proc.pid if self._alive() and self._proc is not None else None

    def _alive(self) -> bool:
        return (self._proc is not None and self._owner == os.getpid()
                and self._proc.poll() is None)

    def _start(self) -> str | None:
        """Start a worker and wait until it is ready; returns why not, or None."""
        self._stderr = tempfile.TemporaryFile()
        self._proc = subprocess.Popen(
            [sys.executable, str(_WORKER_SCRIPT)], stdin=subprocess.PIPE,
            stdout=subprocess.PIPE, stderr=self._stderr, start_new_session=True)
        self._owner, self._buf = os.getpid(), b""
        self.starts += 1
        line = self._read_line(time.perf_counter() + self.START_TIMEOUT)
        if line is None or json.loads(line).get("ready") is not True:
            why = f"the planner worker did not start: {self._stderr_tail()}"
            self.close()
            return why
        return None

    def _read_line(self, deadline: float) -> bytes | None:
        """The worker's next line; None at `deadline` or when its output ended (then
        ``self._eof`` is True: the worker is gone, whether or not it has been reaped)."""
        assert self._proc is not None and self._proc.stdout is not None
        fd = self._proc.stdout.fileno()
        while b"\n" not in self._buf:
            left = deadline - time.perf_counter()
            if left <= 0 or not select.select([fd], [], [], left)[0]:
                return None
            chunk = os.read(fd, 65536)
            if not chunk:
                self._eof = True
                return None
            self._buf += chunk
        line, self._buf = self._buf.split(b"\n", 1)
        return line

    def _stderr_tail(self) -> str:
        if self._stderr is None:
            return ""
        self._stderr.seek(0)
        return self._stderr.read().decode(errors="replace").strip()[-500:]

    def call(self, request: dict[str, Any], time_limit: float) -> tuple[str, Any]:
        """Send `request` and wait at most `time_limit` s for the answer.

        A worker that is gone without answering (killed or crashed between calls, which
        its process's status may not show yet, or during this one) is restarted once and
        asked again within what is left of the time limit; a second worker gone too is an
        error.

        Returns
        -------
        (str, object)
            ``(status, payload)`` as the worker answered, ``("timeout", message)`` after a
            kill at the limit, ``("error", message)`` if the worker died or did not start.
        """
        with self._lock:
            left = time_limit
            why: str | None = None
            for _ in range(2):
                if not self._alive():
                    why = self._start()
                    if why is not None:
                        return "error", why
                t0 = time.perf_counter()
                line = self._exchange(request, t0 + left)
                if line is not None:
                    answer = json.loads(line)
                    return answer["status"], answer["payload"]
                left -= time.perf_counter() - t0
                assert self._proc is not None
                if not self._eof and self._proc.poll() is None:  # searching: the hard limit
                    self.close()
                    return "timeout", f"stopped at the time limit of {time_limit:g} s"
                proc, tail = self._proc, self._stderr_tail()
                self.close()  # reaps it (after a kill, should it still run)
                why = (f"the planner worker ended without an answer (exit code "
                       f"{proc.returncode}): {tail}")
                if left <= 0:
                    break
            return "error", why

    def _exchange(self, request: dict[str, Any], deadline: float) -> bytes | None:
        """Write `request` to the running worker and read its answer line (None: no answer
        by `deadline`, or the worker is gone: ``self._eof``)."""
        assert self._proc is not None and self._proc.stdin is not None
        self._eof = False
        try:
            self._proc.stdin.write((json.dumps(request) + "\n").encode())
            self._proc.stdin.flush()
        except BrokenPipeError:  # gone before it read the request
            self._eof = True
            return None
        return self._read_line(deadline)

    def close(self) -> None:
        """Kill the worker (its whole process group) if this process started it."""
        proc, self._proc = self._proc, None
        if proc is not None and self._owner == os.getpid():
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                proc.kill()
            proc.wait()
            for f in (proc.stdin, proc.stdout):
                if f is not None:
                    # a request still buffered for a dead worker cannot be flushed
                    with contextlib.suppress(OSError):
                        f.close()
        if self._stderr is not None:
            self._stderr.close()
            self._stderr = None


#: The worker every :func:`solve_files` call of this process uses.
WORKER = PlannerWorker()
atexit.register(WORKER.close)


def solve_files(domain: str | os.PathLike[str], problem: str | os.PathLike[str],
                planner: str = "pyperplan", time_limit: float = 10.0,
                search: str = "astar", heuristic: str = "lmcut") -> PlanResult:
    """Solve a PDDL domain and problem file within `time_limit` seconds.

    The planner runs in :data:`WORKER`, a process that stays alive between calls, so a
    call pays no process start-up or import (but the first, which starts the worker).

    Parameters
    ----------
    domain, problem : str or PathLike
        PDDL files.
    planner : {"pyperplan", "fast-downward"}
        Which planner.
    time_limit : float
        s, > 0: the call returns by then (plus the time to kill the worker), the worker's
        start-up (once per process, and after a kill) not counted.
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
    status, payload = WORKER.call({"planner": planner, "domain": str(Path(domain).resolve()),
                                   "problem": str(Path(problem).resolve()), "search": search,
                                   "heuristic": heuristic}, time_limit)
    elapsed = time.perf_counter() - t0
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
