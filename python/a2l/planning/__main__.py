"""Rerun a written planning task: ``python -m a2l.planning DOMAIN PROBLEM [--planner P]``."""

from __future__ import annotations

import argparse
import sys

from a2l.planning.planners import PLANNERS, solve_files


def main(argv: list[str] | None = None) -> int:
    """Solve DOMAIN and PROBLEM, print the report; exit 0 if solved, 1 if not."""
    ap = argparse.ArgumentParser(prog="python -m a2l.planning", description=__doc__)
    ap.add_argument("domain")
    ap.add_argument("problem")
    ap.add_argument("--planner", choices=PLANNERS, default="pyperplan")
    ap.add_argument("--time-limit", type=float, default=10.0, help="s (default 10)")
    ap.add_argument("--search", default="astar", help="pyperplan search (default astar)")
    ap.add_argument("--heuristic", default="lmcut", help="pyperplan heuristic (default lmcut)")
    a = ap.parse_args(argv)
    res = solve_files(a.domain, a.problem, a.planner, a.time_limit, a.search, a.heuristic)
    print(res.report())
    return 0 if res.solved else 1


if __name__ == "__main__":
    sys.exit(main())
