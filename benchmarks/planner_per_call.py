"""The planner child process that a2l.planning ran once per call before the planner worker
(the baseline of `bench_task_planning.py`): runs one planner, prints JSON. Its pyperplan
search is the worker's own (:func:`a2l.planning._worker.pyperplan_search`), so the two differ
only in the process started per call; its Fast Downward call is the old one through
unified-planning, verbatim.

It ran as ``python -m a2l.planning._child '{"planner": ..., "domain": ..., "problem": ...}'``
(importing the a2l package first); the benchmark runs it the same way through ``runpy``. It
prints ``{"status": ..., "payload": ...}`` on its last line of output.
"""

from __future__ import annotations

import json
import sys
from typing import Any

from a2l.planning._worker import pyperplan_search


def _fast_downward(domain: str, problem: str, time_limit: float) -> tuple[str, Any]:
    from unified_planning.engines import PlanGenerationResultStatus as S
    from unified_planning.io import PDDLReader
    from unified_planning.shortcuts import OneshotPlanner, get_environment

    get_environment().credits_stream = None
    task = PDDLReader().parse_problem(domain, problem)
    with OneshotPlanner(name="fast-downward") as planner:
        res = planner.solve(task, timeout=time_limit)
    if res.status in (S.SOLVED_SATISFICING, S.SOLVED_OPTIMALLY):
        return "solved", [(a.action.name, tuple(str(p) for p in a.actual_parameters))
                          for a in res.plan.actions]
    if res.status in (S.UNSOLVABLE_PROVEN, S.UNSOLVABLE_INCOMPLETELY):
        return "unsolvable", f"Fast Downward (LAMA-first) reports {res.status.name}"
    if res.status == S.TIMEOUT:
        return "timeout", "Fast Downward reached the time limit"
    return "error", f"Fast Downward ended with {res.status.name}: {res.log_messages}"


def main(argv: list[str] | None = None) -> int:
    """Run the planner named in the JSON argument and print the outcome as JSON."""
    args = json.loads((argv if argv is not None else sys.argv[1:])[0])
    try:
        if args["planner"] == "pyperplan":
            status, payload = pyperplan_search(args["domain"], args["problem"],
                                               args["search"], args["heuristic"])
        else:
            status, payload = _fast_downward(args["domain"], args["problem"],
                                             args["time_limit"])
    except Exception as exc:  # reported to the parent, which names it
        status, payload = "error", f"{type(exc).__name__}: {exc}"
    print("\n" + json.dumps({"status": status, "payload": payload}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
