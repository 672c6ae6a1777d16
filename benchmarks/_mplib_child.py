"""Plan the transit benchmark's pairs with mplib, in mplib's own environment.

Run by ``_transit_peers.py`` with the Python of the virtual environment that holds mplib
(``make bench`` makes it: mplib 0.2.1 pins numpy < 2 and crashes under numpy 2, which the rest
of a2l needs). Imports nothing of a2l.

Usage: ``python _mplib_child.py PROBLEM.json RESULT.json``. The problem: ``urdf``,
``move_group``, ``arm_joints`` (names, base to tip), ``other_joints`` (name -> position),
``boxes`` ([name, centre (3,), half-extents (3,)]), ``pairs`` ([start (n,), goal (n,)]),
``neutral`` (n,: the pairs in contact there are allowed), ``time_limit`` (s). The result,
one entry per pair: ``ok``, ``status``, ``time_s`` (wall time of the OMPL call that
``Planner.plan_qpos`` makes, with its defaults: simplification included, time
parameterisation not), ``waypoints``.
"""

from __future__ import annotations

import json
import sys
import time

import mplib
import numpy as np
from mplib.collision_detection import fcl


def main(problem_path: str, result_path: str) -> int:
    with open(problem_path) as f:
        pb = json.load(f)
    t0 = time.perf_counter()
    planner = mplib.Planner(pb["urdf"], move_group=pb["move_group"])
    setup_s = time.perf_counter() - t0
    for name, centre, half in pb["boxes"]:
        box = fcl.Box([2 * h for h in half])
        obj = fcl.CollisionObject(box, mplib.Pose(p=centre))
        planner.planning_world.add_object(name, obj)
    names = list(planner.user_joint_names)
    full = np.zeros(len(names))
    for n, v in pb["other_joints"].items():
        if n in names:
            full[names.index(n)] = v
    arm = [names.index(n) for n in pb["arm_joints"]]
    assert list(planner.move_group_joint_indices) == arm, (planner.move_group_joint_indices, arm)
    # as the other planners: the pairs in contact at the neutral pose are allowed (mplib's
    # generated SRDF leaves some touching links, and the pedestal on the floor)
    q = full.copy()
    q[arm] = pb["neutral"]
    planner.robot.set_qpos(q, True)
    for c in planner.planning_world.check_collision():
        a = c.link_name1 if c.object_name1 == "baxter" else c.object_name1
        b = c.link_name2 if c.object_name2 == "baxter" else c.object_name2
        planner.acm.set_entry(a, b, True)
    mplib.set_global_seed(0)
    out = []
    for start, goal in pb["pairs"]:
        q = full.copy()
        q[arm] = start
        planner.robot.set_qpos(q, True)
        t, c = time.perf_counter(), time.thread_time()
        status, path = planner.planner.plan(np.asarray(start, float), [np.asarray(goal, float)],
                                            time=pb["time_limit"], range=0.1,
                                            simplify=True)  # plan_qpos' defaults
        dt, cpu = time.perf_counter() - t, time.thread_time() - c
        ok = status == "Exact solution"
        out.append({"ok": ok, "status": status, "time_s": dt, "cpu_s": cpu,
                    "waypoints": np.asarray(path).tolist() if ok else []})
    with open(result_path, "w") as f:
        json.dump({"setup_s": setup_s, "version": mplib.__version__, "results": out}, f)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
