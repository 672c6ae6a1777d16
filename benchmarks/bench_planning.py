"""Planning: a2l's OMPL transit against mplib and pybullet-planning on the same Baxter pairs
(``_transit_peers.py``; PDDL planner calls: ``bench_task_planning.py``)."""

from __future__ import annotations

import sys
import time
from pathlib import Path

from a2l import _core

TITLE = "Planning (OMPL transit on Baxter's right arm)"


def run() -> str:
    parts = []
    if _core.transit_available():
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from _transit_peers import BEFORE, run_all

        parts.append("### Transit against the peers (a2l: C++ OMPL RRT-Connect + Bullet; "
                     "mplib; pybullet-planning)\n\n" + run_all(BEFORE))
    else:
        parts.append("Transit: not measured (this build has no Bullet/OMPL).")
    t = time.strftime("%H:%M")
    return "\n\n".join(parts) + f"\n\n_(section finished at {t})_"
