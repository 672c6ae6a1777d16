"""Planning: OMPL transit among the table's obstacles (PDDL planner calls:
``bench_task_planning.py``)."""

from __future__ import annotations

import os
import time

import numpy as np

import a2l
from a2l import _core

TITLE = "Planning (OMPL transit on Baxter's right arm)"
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


def run() -> str:
    parts = []
    if _core.transit_available():
        parts.append("### Transit (C++: OMPL RRT-Connect + Bullet collision shapes)\n\n"
                     + _transit_table())
    else:
        parts.append("Transit: not measured (this build has no Bullet/OMPL).")
    t = time.strftime("%H:%M")
    return "\n\n".join(parts) + f"\n\n_(section finished at {t})_"
