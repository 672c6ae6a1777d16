"""Simulation: physics steps per second, ms per discrete movement, ms per perceived camera
frame, for every scene of :mod:`a2l.sim` (DIRECT mode, the software renderer)."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from a2l.sim import DIRECTIONS, make_scene
from a2l.sim.bullet import BulletScene

TITLE = "Simulation (a2l.sim scenes: physics, discrete movements, camera perception)"

N_STEPS = 2000  # physics steps timed per scene
N_MOVES = 60  # discrete movements timed per scene
N_FRAMES = 40  # camera frames timed per scene and robot drawing


def _times(fn: Callable[[], object], n: int) -> np.ndarray:
    out = np.empty(n)
    for i in range(n):
        t = time.perf_counter()
        fn()
        out[i] = time.perf_counter() - t
    return out


def _moves(scene, rng: np.random.Generator
           ) -> tuple[np.ndarray, dict[str, int], int, np.ndarray]:
    """Time N_MOVES random discrete movements from a start in front of the primary object,
    and a perception after each; return the movement times (s), the count of each status,
    the physics steps the movements took and the perception times (s)."""
    home = np.asarray(scene.ground_truth()["objects"][scene.primary_object])
    start = home + np.array([-0.15, 0.0, 0.05])
    scene.reset(eef=start)
    times, seen, statuses = [], [], {}
    ticks = 0
    for _ in range(N_MOVES):
        d = DIRECTIONS[rng.integers(len(DIRECTIONS))]
        t0 = getattr(scene, "_tick", 0)
        t = time.perf_counter()
        result = scene.execute(d)
        times.append(time.perf_counter() - t)
        ticks += getattr(scene, "_tick", 0) - t0
        statuses[result.status] = statuses.get(result.status, 0) + 1
        t = time.perf_counter()
        scene.perceive()
        seen.append(time.perf_counter() - t)
        if np.linalg.norm(scene.eef_position() - start) > 0.15:
            scene.reset(eef=start)
    return np.asarray(times), statuses, ticks, np.asarray(seen)


def _row_cells(name: str) -> dict[str, str]:
    rng = np.random.default_rng(0)
    t = time.perf_counter()
    scene = make_scene(name, seed=0, context_source="ground_truth")
    build = time.perf_counter() - t
    cells: dict[str, str] = {"scene": f"`{name}`", "build (s)": f"{build:.2f}"}
    try:
        move_t, statuses, ticks, seen_t = _moves(scene, rng)
        cells["ms / movement (median, p90)"] = (
            f"{np.median(move_t) * 1e3:.2f}, {np.percentile(move_t, 90) * 1e3:.2f}")
        cells["movement statuses"] = ", ".join(
            f"{k} {v}" for k, v in sorted(statuses.items(), key=lambda kv: -kv[1]))
        if isinstance(scene, BulletScene):
            scene.reset()
            step_t = _times(lambda: scene.settle(scene.config.time_step), N_STEPS)
            cells["physics steps / s"] = f"{1.0 / np.median(step_t):,.0f}"
            cells["steps / movement"] = f"{ticks / N_MOVES:.0f}"
            frame_t = _times(lambda: scene.perception.locate(*scene.render()), N_FRAMES)
            cells["ms / perceived frame (collision shapes)"] = f"{np.median(frame_t) * 1e3:.1f}"
            cells["ms / perceive() after a movement (median, p90)"] = (
                f"{np.median(seen_t) * 1e3:.1f}, {np.percentile(seen_t, 90) * 1e3:.1f}")
        else:
            cells["ms / perceive() after a movement (median, p90)"] = "-"
            cells["physics steps / s"] = "- (no physics)"
            cells["steps / movement"] = "-"
            cells["ms / perceived frame (collision shapes)"] = "- (no camera)"
    finally:
        scene.close()
    if name != "virtual":
        with make_scene(name, seed=0, robot_visual="mesh") as mesh:
            frame_t = _times(lambda: mesh.perception.locate(*mesh.render()),
                             max(10, N_FRAMES // 4))
            cells["ms / perceived frame (visual meshes)"] = f"{np.median(frame_t) * 1e3:.1f}"
    else:
        cells["ms / perceived frame (visual meshes)"] = "-"
    return cells


def run() -> str:
    rows = [_row_cells(name) for name in ("push", "grasp", "press", "virtual")]
    cols = list(rows[0])
    for r in rows[1:]:
        cols += [c for c in r if c not in cols]
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in rows:
        lines.append("| " + " | ".join(r.get(c, "-") for c in cols) + " |")
    return "\n".join(lines) + (
        "\n\nA movement is one of the 26 discrete directions (5 cm), drawn at random from a "
        "start 15 cm in front of the scene's object (back to the start when it wanders "
        "off): straight-line waypoints every 1 cm solved by the C++ IK, joint position "
        "control at 240 Hz, until the end-effector settles (PyBullet scenes); one call of "
        "the C++ `VirtualScene` (virtual). A perceived frame is one 320x240 render by "
        "PyBullet's software renderer plus the OpenCV segmentation and depth lifting of "
        "every object (and the lamp) in the main camera; the robot is drawn with its collision "
        "shapes (the default; torso and pedestal as boxes) or with its visual meshes. "
        "`perceive()` renders the main camera, and the side cameras only when the arm hides "
        "part of an object from it. Physics steps/s: `stepSimulation` with the arm holding "
        "its pose, objects at rest. Movement statuses: `workspace_limit` = the target was "
        "below the table-top clearance or outside the bounds (nothing moved), `blocked` = "
        "an object or the button stopped the arm short of the target.\n")


if __name__ == "__main__":
    print(run())
