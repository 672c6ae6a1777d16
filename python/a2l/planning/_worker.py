"""The planner worker of :mod:`a2l.planning.planners`: a child process that stays alive
between planner calls.

Run by path, ``python .../a2l/planning/_worker.py`` (not as ``-m``: it needs neither a2l
nor numpy, and starts in a fraction of the time a2l's import takes). It imports pyperplan
and Fast Downward's translator once, prints ``{"ready": true}``, then answers one request
a line on standard input (``{"planner": ..., "domain": ..., "problem": ..., "search": ...,
"heuristic": ...}``) with ``{"status": ..., "payload": ...}`` on one line of its standard
output. Whatever a planner prints goes to standard error, so the answers are the only lines
on standard output.

- pyperplan: its Python API (``search_plan``) in this process.
- Fast Downward: the translator (``fast_downward.translate``, shipped with
  ``up-fast-downward``) in this process, then the compiled ``downward`` search binary of
  ``up-fast-downward`` run on the translated task with the driver's ``lama-first`` search
  options (the configuration unified-planning's ``OneshotPlanner(name="fast-downward")``
  runs), its exit code read as the driver reads it.

The worker has no time limit of its own: the parent kills its process group (this process
and a running ``downward``) at the limit and starts a new worker.
"""

from __future__ import annotations

import contextlib
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

# run by path, Python puts this file's directory first on sys.path: its modules
# (pddl.py, ...) must not shadow top-level modules a planner imports
if sys.path and Path(sys.path[0]).resolve() == Path(__file__).resolve().parent:
    del sys.path[0]

#: Exit codes of Fast Downward's search that mean "no plan" (``driver/returncodes.py``:
#: TRANSLATE_UNSOLVABLE, SEARCH_UNSOLVABLE, SEARCH_UNSOLVED_INCOMPLETE,
#: SEARCH_UNSOLVABLE_WITHIN_BOUND).
_FD_UNSOLVABLE = {10: "proven", 11: "proven", 12: "incompletely", 13: "within its bound"}


def _downward_dir() -> Path:
    spec = importlib.util.find_spec("up_fast_downward")
    if spec is None or spec.origin is None:
        raise FileNotFoundError("up-fast-downward is not installed")
    return Path(spec.origin).parent / "downward"


def _lama_first() -> list[str]:
    """The search options of the ``lama-first`` alias, read from the shipped driver."""
    root = str(_downward_dir())
    if root not in sys.path:
        sys.path.append(root)
    from driver.aliases import ALIASES  # the driver package of up-fast-downward

    return list(ALIASES["lama-first"])


def pyperplan_search(domain: str, problem: str, search: str, heuristic: str) -> tuple[str, Any]:
    """One pyperplan search on PDDL files `domain` and `problem` (paths) in this process.

    Returns
    -------
    tuple
        ``("solved", [(action, (args, ...)), ...])``, ``("unsolvable", why)`` or
        ``("error", why)`` for an unknown search or heuristic name.
    """
    from pyperplan import planner as pp

    searches = pp.SEARCHES
    heuristics = pp.HEURISTICS
    if not isinstance(heuristics, dict):  # older releases: a list of classes
        heuristics = {h.__name__[:-len("Heuristic")].lower(): h for h in heuristics}
    if search not in searches:
        return "error", f"unknown pyperplan search {search!r}; choose from {sorted(searches)}"
    if heuristic not in heuristics:
        return "error", (f"unknown pyperplan heuristic {heuristic!r}; choose from "
                         f"{sorted(heuristics)}")
    blind_search = search in ("bfs", "ids", "sat")
    plan = pp.search_plan(domain, problem, searches[search],
                          None if blind_search else heuristics[heuristic])
    if plan is None:
        if search in ("ehs", "ids", "sat"):  # incomplete or bounded: no proof
            return "unsolvable", f"pyperplan's {search} search found no plan (not a proof)"
        return "unsolvable", f"pyperplan's {search} search exhausted the state space"
    return "solved", [_step(op.name) for op in plan]


def _step(text: str) -> tuple[str, tuple[str, ...]]:
    tokens = text.strip().strip("()").split()
    return tokens[0], tuple(tokens[1:])


class _FastDownward:
    """The translator in this process and the ``downward`` binary per call."""

    def __init__(self) -> None:
        from fast_downward.translate import main as translate
        from fast_downward.translate import options

        self._translate, self._options = translate, options
        self._binary = _downward_dir() / "builds" / "release" / "bin" / "downward"
        self._search = _lama_first()
        self._tmp = tempfile.mkdtemp(prefix="a2l-fd-")

    def solve(self, domain: str, problem: str) -> tuple[str, Any]:
        sas, plan = os.path.join(self._tmp, "output.sas"), os.path.join(self._tmp, "sas_plan")
        for f in (sas, plan):
            with contextlib.suppress(FileNotFoundError):
                os.remove(f)
        self._options.set_options([domain, problem, "--sas-file", sas])
        try:
            self._translate.main()
        except SystemExit as exc:  # the translator exits on some input errors
            return "error", f"Fast Downward's translator exited ({exc.code})"
        with open(sas, "rb") as task:
            run = subprocess.run([str(self._binary), *self._search, "--internal-plan-file",
                                  plan], stdin=task, stdout=subprocess.PIPE,
                                 stderr=subprocess.STDOUT, cwd=self._tmp, check=False)
        code = run.returncode
        if code == 0 and os.path.exists(plan):
            with open(plan) as f:
                return "solved", [_step(line) for line in f
                                  if line.strip() and not line.startswith(";")]
        if code in _FD_UNSOLVABLE:
            return "unsolvable", (f"Fast Downward (LAMA-first) reports the task unsolvable "
                                  f"({_FD_UNSOLVABLE[code]}, exit code {code})")
        tail = run.stdout.decode(errors="replace").strip()[-500:]
        return "error", f"Fast Downward's search ended with exit code {code}: {tail}"


def main() -> int:
    """Serve planner requests from standard input until it closes."""
    answers = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)  # anything a planner prints (Python or C) goes to standard error
    sys.stdout = sys.stderr
    import pyperplan.planner  # noqa: F401  (imported once, before the first call)

    fast_downward: _FastDownward | None = None
    fd_error = ""
    try:
        fast_downward = _FastDownward()
    except Exception as exc:  # reported when Fast Downward is asked for
        fd_error = f"Fast Downward is not available: {type(exc).__name__}: {exc}"
    answers.write(json.dumps({"ready": True}) + "\n")
    answers.flush()
    for line in sys.stdin:
        if not line.strip():
            continue
        try:
            req = json.loads(line)
            if req["planner"] == "pyperplan":
                status, payload = pyperplan_search(req["domain"], req["problem"], req["search"],
                                             req["heuristic"])
            elif fast_downward is None:
                status, payload = "error", fd_error
            else:
                status, payload = fast_downward.solve(req["domain"], req["problem"])
        except Exception as exc:  # reported to the parent, which names it
            status, payload = "error", f"{type(exc).__name__}: {exc}"
        answers.write(json.dumps({"status": status, "payload": payload}) + "\n")
        answers.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
