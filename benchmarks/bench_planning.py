"""Planning: OMPL transit among the table's obstacles, and PDDL planning time per planner."""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import a2l
from a2l import _core

TITLE = "Planning (OMPL transit on Baxter's right arm; PDDL planners)"
N_PAIRS = 100
SEED = 0


def _random_configs(scene, transit, rng, n: int) -> list[np.ndarray]:
    """`n` collision-free arm configurations with the gripper pointing down, 2-25 cm above
    the table anywhere over the press scene's table (box, button, lamp)."""
    cfg = scene.config
    kin = scene.kinematics
    lo = np.array(cfg.workspace_min[:2])
    hi = np.array(cfg.workspace_max[:2])
    out = []
    seed_q = scene.joint_positions()
    while len(out) < n:
        xy = rng.uniform(lo, hi)
        z = cfg.table_z + rng.uniform(0.02, 0.25)
        t = np.eye(4)
        t[:3, :3] = np.diag([-1.0, 1.0, -1.0])
        t[:3, 3] = (xy[0], xy[1], z)
        q, rep = kin.ik_report(t, seed_q)
        if rep.status == a2l.Status.ok and not transit.in_collision(q):
            out.append(q)
    return out


def _transit_table() -> str:
    from a2l.planning.transit import ArmTransit
    from a2l.sim import make_scene

    load = os.getloadavg()[0]
    rng = np.random.default_rng(SEED)
    with make_scene("press", seed=SEED) as scene:
        transit = ArmTransit("baxter", "right", time_limit=2.0)
        transit.sync(scene)
        configs = _random_configs(scene, transit, rng, 2 * N_PAIRS)
    times, ok, lengths, durations, checks, failures = [], 0, [], [], [], []
    for i in range(N_PAIRS):
        c0 = transit.planner.collision_checks
        r = transit.plan(configs[2 * i], configs[2 * i + 1], seed=SEED + i)
        times.append(r.planning_time * 1000)
        checks.append(transit.planner.collision_checks - c0)
        if r.ok:
            ok += 1
            lengths.append(r.path_length)
            durations.append(r.duration)
        else:
            failures.append(f"pair {i}: {r.status}")
    t = np.array(times)
    rows = [
        "| pairs | success | median ms | p95 ms | max ms | collision checks / call (median) "
        "| path length rad (median) | trajectory s (median) |",
        "|---|---|---|---|---|---|---|---|",
        f"| {N_PAIRS} | {ok}/{N_PAIRS} | {np.median(t):.1f} | {np.percentile(t, 95):.1f} | "
        f"{t.max():.1f} | {np.median(checks):.0f} | {np.median(lengths):.2f} | "
        f"{np.median(durations):.2f} |",
    ]
    return (
        "Start and goal: random gripper-down poses 2-25 cm above the table of the press "
        "scene (box, button with its housing, lamp, table top as obstacles padded by 2 cm; "
        f"self-collision with the rest of Baxter), seed {SEED}. RRT-Connect, time limit 2 s "
        "per call, collision checks every 0.01 rad, path shortening, trajectory within 0.5 x "
        "the URDF velocity limits and 1.5 rad/s^2 (`ArmTransit` defaults). Planning time "
        "includes shortening and time parameterisation. Load average of the machine at the "
        f"start: {load:.1f} (2 cores shared).\n\n" + "\n".join(rows)
        + ("\n\nFailures: " + "; ".join(failures) + "." if failures else "")
    )


def _pddl_table() -> str:
    from a2l.planning import (
        PerceivedState,
        TableRegions,
        domain_pddl,
        problem_pddl,
        solve,
        tabletop_repertoire,
    )

    pushes = ("left", "right", "close", "far")
    regions = TableRegions(center=(0.75, -0.15), size=(0.7, 1.2))
    skills = tabletop_repertoire(pushes)
    state = PerceivedState(regions.names, {"block": "mid-centre", "box": "mid-right"},
                           ("button",), {"light": "on", "gripper": "open"},
                           static=regions.neighbour_facts(pushes))
    tasks = {
        "light off": "(light-off)",
        "light off, block far-left, box close-right":
            "(and (light-off) (at block far-left) (at box close-right))",
        "block far-left, box far-right, light on, gripper closed":
            "(and (at block far-left) (at box far-right) (light-on) (gripper-closed))",
        "impossible (held and on the table)": "(and (holding block) (at block far-left))",
    }
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", "import unified_planning.shortcuts, up_fast_downward"],
                   check=True)
    up_import_ms = (time.perf_counter() - t0) * 1000
    rows = ["| task | planner | status | steps | wall ms (median of 3) |", "|---|---|---|---|---|"]
    dom = domain_pddl(skills)
    with tempfile.TemporaryDirectory() as tmp:
        for name, goal in tasks.items():
            prob = problem_pddl(skills, state, goal)
            for planner in ("pyperplan", "fast-downward"):
                res = [solve(dom, prob, tmp, planner=planner, time_limit=60) for _ in range(3)]
                ms = np.median([r.time_s * 1000 for r in res])
                rows.append(f"| {name} | {planner} | {res[0].status} | "
                            f"{len(res[0].plan) if res[0].solved else '-'} | {ms:.0f} |")
    return ("Repertoire: push left/right/close/far, grasp, place, press (learned with the "
            "gripper closed; one operator per light transition), open/close gripper; 3 x 3 "
            "table regions. pyperplan: A* + LM-cut; Fast Downward: LAMA-first through "
            "unified-planning. Wall time of `a2l.planning.solve`: writing the files, the "
            "child process that runs the planner (start-up included) and reading the "
            f"plan. A bare Python start that imports unified-planning and up-fast-downward "
            f"took {up_import_ms:.0f} ms here: most of Fast Downward's time. Load average at "
            f"the start: {os.getloadavg()[0]:.1f}.\n\n" + "\n".join(rows))


def _experiment_tasks_table() -> str:
    """Both planners on the start states of ``a2l experiment tasks``' tasks."""
    from a2l.experiments.task_trials import TASKS, task_skills
    from a2l.planning import PerceivedState, TableRegions, domain_pddl, problem_pddl, solve

    regions = TableRegions(center=(0.75, -0.15), size=(0.7, 1.2))
    skills = task_skills()
    dom = domain_pddl(skills)
    rows = ["| task | start -> goal | planner | status | steps | wall ms (median of 3) |",
            "|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as tmp:
        for name, spec in TASKS.items():
            for light in ([spec.light] if spec.light else ["on", "off"]):
                goal = spec.goal(np.random.default_rng(0))
                state = PerceivedState(regions.names, {"block": spec.start_region},
                                       ("button",), {"light": light, "gripper": spec.gripper})
                prob = problem_pddl(skills, state, goal)
                for planner in ("pyperplan", "fast-downward"):
                    res = [solve(dom, prob, tmp, planner=planner, time_limit=60)
                           for _ in range(3)]
                    ms = np.median([r.time_s * 1000 for r in res])
                    rows.append(f"| {name} | light {light}, gripper {spec.gripper}, block "
                                f"{spec.start_region} -> `{goal}` | {planner} | "
                                f"{res[0].status} | "
                                f"{len(res[0].plan) if res[0].solved else '-'} | {ms:.0f} |")
    return ("The tasks of `a2l experiment tasks` from their start states (repertoire: grasp, "
            "place, press-light-on/off, open/close gripper; the block the only movable). "
            f"Load average at the start: {os.getloadavg()[0]:.1f}.\n\n" + "\n".join(rows))


def run() -> str:
    parts = []
    if _core.transit_available():
        parts.append("### Transit (C++: OMPL RRT-Connect + Bullet collision shapes)\n\n"
                     + _transit_table())
    else:
        parts.append("Transit: not measured (this build has no Bullet/OMPL).")
    parts.append("### Task planning (PDDL)\n\n" + _pddl_table())
    parts.append("### The experiment's tasks (PDDL)\n\n" + _experiment_tasks_table())
    t = time.strftime("%H:%M")
    return "\n\n".join(parts) + f"\n\n_(section finished at {t})_"
