"""The ``a2l demo`` job (for now): Baxter pushes a box on a table in PyBullet.

The right end-effector starts 15 cm in front of the box, gripper pointing down, and moves
forward in discrete 5 cm movements, each solved by the C++ inverse kinematics
(:class:`a2l.Kinematics`) and carried out by joint position control, until it has gone
past where the box was. The demo prints every movement, the effect it produced and how
far the box moved (ground truth and camera perception). Later issues turn this command
into the whole A2L pipeline.
"""

from __future__ import annotations

import time

import numpy as np

__all__ = ["run_demo"]

#: The box must move at least this far (m) for the demo to succeed.
MIN_DISPLACEMENT = 0.01


def run_demo(seed: int = 0, gui: bool = False, max_moves: int = 6) -> int:
    """Run the demo and print what happened.

    Parameters
    ----------
    seed : int
        Seed of the scene.
    gui : bool
        Open the PyBullet GUI and run in real time.
    max_moves : int
        Most forward movements to try.

    Returns
    -------
    int
        0 when the box moved at least :data:`MIN_DISPLACEMENT`, 1 when it did not, 2 when
        the scene could not be built (e.g. the GUI without a display).
    """
    from a2l.errors import A2LError
    from a2l.sim import make_scene

    t0 = time.perf_counter()
    try:
        scene = make_scene("push", seed=seed, gui=gui)
    except A2LError as exc:
        print(f"FAILED: cannot build the scene: {exc}")
        return 2
    with scene:
        box0 = np.asarray(scene.ground_truth()["objects"]["box"])
        seen0 = scene.perceive()["objects"].get("box")
        start = box0 + np.array([-0.15, 0.0, -0.01])
        scene.reset(eef=start)
        print(f"a2l demo (seed {seed}): Baxter's right gripper pushes a box in PyBullet, "
              "moving by the C++ inverse kinematics")
        print(f"  box at ({box0[0]:.3f}, {box0[1]:.3f}, {box0[2]:.3f}) m; end-effector starts "
              f"at ({start[0]:.3f}, {start[1]:.3f}, {start[2]:.3f}) m")
        for i in range(1, max_moves + 1):
            result = scene.execute((1, 0, 0))
            eef = result.reached
            effect = scene.observe_effect(source="ground_truth")
            print(f"  move {i}: +x {scene.step_length * 100:.0f} cm -> {result.status:<8} "
                  f"end-effector ({eef[0]:.3f}, {eef[1]:.3f}, {eef[2]:.3f}), effect {effect}")
            if not result:
                print(f"  movement not carried out: {result.message}")
                break
            if eef[0] > box0[0] + 0.02:
                break
        box1 = np.asarray(scene.ground_truth()["objects"]["box"])
        seen1 = scene.perceive()["objects"].get("box")
        moved = float(np.linalg.norm((box1 - box0)[:2]))
        print(f"  box moved {moved * 100:.1f} cm (ground truth), to "
              f"({box1[0]:.3f}, {box1[1]:.3f}, {box1[2]:.3f}) m; "
              f"effect over the episode: {scene.observe_effect('episode', 'ground_truth')}")
        if seen0 is not None and seen1 is not None:
            seen = float(np.linalg.norm((np.asarray(seen1) - np.asarray(seen0))[:2]))
            print(f"  the camera saw it move {seen * 100:.1f} cm")
    print(f"  ({time.perf_counter() - t0:.1f} s)")
    if moved < MIN_DISPLACEMENT:
        print(f"FAILED: the box moved {moved * 1000:.1f} mm, less than "
              f"{MIN_DISPLACEMENT * 1000:.0f} mm")
        return 1
    print("OK: the box moved")
    return 0
