"""Task planning: PDDL planner calls in the planner worker against a process per call.

Before the planner worker, every call started a child process (``python -m
a2l.planning._child``: the a2l package, the planner and, for Fast Downward, unified-planning
imported per call); that child is kept as ``planner_per_call.py`` (its pyperplan search the
worker's own function, so the rows differ only in the process per call) and timed here
as the baseline row, in the same run as the worker (:data:`a2l.planning.planners.WORKER`).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

TITLE = "Task planning (PDDL planner calls: the planner worker against a process per call)"
PACKAGES = ("pyperplan", "up-fast-downward", "unified-planning")
HERE = Path(__file__).resolve().parent
#: calls per task and planner: the process per call (slow) and the worker
N_BEFORE, N_AFTER = 3, 10
_RUN_OLD = ("import runpy, sys, a2l.planning; "
            f"runpy.run_path({str(HERE / 'planner_per_call.py')!r}, run_name='__main__')")


def _per_call(planner: str, domain: Path, problem: Path) -> tuple[float, str, int]:
    """The old path: one child process per call. Returns (ms, status, plan length)."""
    args = {"planner": planner, "domain": str(domain), "problem": str(problem),
            "search": "astar", "heuristic": "lmcut", "time_limit": 60.0}
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", _RUN_OLD, json.dumps(args)], check=True,
                         capture_output=True, text=True, start_new_session=True, timeout=120)
    ms = (time.perf_counter() - t0) * 1000
    answer = json.loads(out.stdout.strip().splitlines()[-1])
    steps = len(answer["payload"]) if answer["status"] == "solved" else -1
    return ms, answer["status"], steps


def _tasks() -> list[tuple[str, str, str, str]]:
    """(group, task, domain, problem): the tabletop repertoire's tasks and the tasks
    experiment's tasks from their start states."""
    from a2l.experiments.task_trials import TASKS, task_skills
    from a2l.planning import (
        PerceivedState,
        TableRegions,
        domain_pddl,
        problem_pddl,
        tabletop_repertoire,
    )

    pushes = ("left", "right", "close", "far")
    regions = TableRegions(center=(0.75, -0.15), size=(0.7, 1.2))
    out = []
    skills = tabletop_repertoire(pushes)
    state = PerceivedState(regions.names, {"block": "mid-centre", "box": "mid-right"},
                           ("button",), {"light": "on", "gripper": "open"},
                           static=regions.neighbour_facts(pushes))
    for name, goal in {
        "light off": "(light-off)",
        "light off, block far-left, box close-right":
            "(and (light-off) (at block far-left) (at box close-right))",
        "block far-left, box far-right, light on, gripper closed":
            "(and (at block far-left) (at box far-right) (light-on) (gripper-closed))",
        "impossible (held and on the table)": "(and (holding block) (at block far-left))",
    }.items():
        out.append(("repertoire", name, domain_pddl(skills), problem_pddl(skills, state, goal)))
    skills = task_skills()
    for name, spec in TASKS.items():
        for light in ([spec.light] if spec.light else ["on", "off"]):
            goal = spec.goal(np.random.default_rng(0))
            state = PerceivedState(regions.names, {"block": spec.start_region}, ("button",),
                                   {"light": light, "gripper": spec.gripper})
            out.append(("experiment", f"{name} (light {light}) -> `{goal}`",
                        domain_pddl(skills), problem_pddl(skills, state, goal)))
    return out


def run() -> str:
    from a2l.planning import solve_files, write_task
    from a2l.planning.planners import WORKER

    load = os.getloadavg()[0]
    rows = {"repertoire": [], "experiment": []}
    after_ms: dict[tuple[str, str], list[float]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        tasks = [(g, n, *write_task(tmp, d, p, name=f"t{i}"))
                 for i, (g, n, d, p) in enumerate(_tasks())]
        t0 = time.perf_counter()
        first = solve_files(tasks[0][2], tasks[0][3], "pyperplan", time_limit=60)
        start_ms = (time.perf_counter() - t0) * 1000
        assert first.solved, first.report()
        for group, name, dom, prob in tasks:
            for planner in ("pyperplan", "fast-downward"):
                before = [_per_call(planner, dom, prob) for _ in range(N_BEFORE)]
                after = [solve_files(dom, prob, planner, time_limit=60)
                         for _ in range(N_AFTER)]
                b_ms = float(np.median([b[0] for b in before]))
                a_ms = [r.time_s * 1000 for r in after]
                after_ms.setdefault((group, planner), []).extend(a_ms)
                st_b = {(b[1], b[2]) for b in before}
                st_a = {(r.status, len(r.plan) if r.solved else -1) for r in after}
                same = "" if st_b == st_a else f" (before: {sorted(st_b)})"
                status, steps = next(iter(st_a)) if len(st_a) == 1 else ("mixed", -1)
                rows[group].append(
                    f"| {name} | {planner} | {status}{same} | {steps if steps >= 0 else '-'} "
                    f"| {b_ms:.0f} | {np.median(a_ms):.1f} | {max(a_ms):.1f} | "
                    f"{b_ms / np.median(a_ms):.0f} |")
    head = ["| task | planner | status | steps | process per call ms (before, median of "
            f"{N_BEFORE}) | worker ms (after, median of {N_AFTER}) | worker max ms | "
            "before / after |", "|---|---|---|---|---|---|---|---|"]
    summary = ["| tasks | planner | worker calls | median ms | p95 ms | max ms | target |",
               "|---|---|---|---|---|---|---|"]
    for (group, planner), ms in after_ms.items():
        target = "≤ 50 ms" if planner == "pyperplan" else "≤ 300 ms"
        summary.append(f"| {group} | {planner} | {len(ms)} | {np.median(ms):.1f} | "
                       f"{np.percentile(ms, 95):.1f} | {max(ms):.1f} | {target} |")
    return (
        "Wall time of `a2l.planning.solve_files` on PDDL files written once (after: the "
        "task sent to the planner worker, the search, the plan read back) against the "
        "child process per call it replaces (before: `python -m a2l.planning._child`, kept "
        "as `benchmarks/planner_per_call.py`, the a2l package, the planner and, for Fast "
        "Downward, unified-planning imported in every call), both measured here in one run. "
        "pyperplan: A* + LM-cut; Fast Downward: LAMA-first (before through unified-planning "
        "and the driver script, after its translator in the worker and the `downward` binary "
        f"per call). The worker's start-up, once per process, took {start_ms:.0f} ms (its "
        f"first call). Load average at the start: {load:.1f} (2 cores shared with other "
        f"jobs).\n\n### Worker calls, all tasks\n\n" + "\n".join(summary)
        + "\n\n### The tabletop repertoire (push left/right/close/far, grasp, place, press, "
        "open/close gripper; 3 x 3 regions)\n\n" + "\n".join(head + rows["repertoire"])
        + "\n\n### The tasks of `a2l experiment tasks` from their start states (grasp, place, "
        "press-light-on/off, open/close gripper; the block the only movable)\n\n"
        + "\n".join(head + rows["experiment"])
        + f"\n\n_(section finished at {time.strftime('%H:%M')}; worker starts: "
        f"{WORKER.starts})_")
