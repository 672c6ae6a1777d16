"""An episode's start is bitwise the same whatever ran before in the process: the same
rollout from the same start gives bitwise-equal end-effector and object positions after
two different histories of episodes (a2l.sim.bodies)."""

from __future__ import annotations

import numpy as np
import pytest

from a2l.sim import make_scene
from a2l.sim.bullet import BulletScene

ROLLOUT = [(1, 0, 0), (1, 0, 0), (1, 1, 0), (1, 0, 0), (0, -1, 0), (1, -1, 0)]
#: Two histories: (end-effector offset from the object, movements) per episode. The second
#: one drags the gripper on the table and leaves it against the object.
HISTORIES = {
    "pushes": [((-0.13, 0.0, 0.0), [(1, 0, 0)] * 4),
               ((-0.10, -0.12, 0.0), [(0, 1, 0), (1, 0, 0), (1, 0, 0)])],
    "table": [((-0.13, -0.10, 0.0), [(0, 0, -1), (0, 0, -1), (1, 0, 0), (1, 0, 0), (1, 1, 0)]),
              ((-0.20, 0.0, 0.0), [(1, 0, -1), (1, 0, 0), (1, 0, 0), (1, 0, 0), (1, 0, 0)]),
              ((-0.15, 0.05, 0.03), [(1, -1, 0), (1, 0, 0)])],
}


def _begin(scene: BulletScene, home: np.ndarray, offset: tuple[float, float, float]) -> None:
    scene.reset(eef=home + np.asarray(offset), objects={scene.primary_object: home[:2]})


def _rollout(scene_name: str, history: str | None) -> np.ndarray:
    """Object and end-effector positions (len(ROLLOUT) + 1, 6) of the rollout, after
    `history` in the same scene (None: in a new scene)."""
    with make_scene(scene_name, seed=0, object_jitter=0.0,
                    context_source="ground_truth") as scene:
        name = scene.primary_object
        home = np.asarray(scene.ground_truth()["objects"][name])
        for offset, moves in HISTORIES.get(history or "", []):
            _begin(scene, home, offset)
            for d in moves:
                scene.execute(d)
        _begin(scene, home, (-0.13, 0.0, 0.0))
        rows = [(*scene.ground_truth()["objects"][name], *scene.eef_position())]
        for d in ROLLOUT:
            scene.execute(d)
            rows.append((*scene.ground_truth()["objects"][name], *scene.eef_position()))
    return np.asarray(rows)


@pytest.mark.parametrize("scene", ["push", "grasp", "press"])
def test_same_start_same_rollout_after_different_histories(scene: str) -> None:
    fresh = _rollout(scene, None)
    for history in HISTORIES:
        after = _rollout(scene, history)
        assert np.array_equal(after, fresh), (history, np.abs(after - fresh).max())
    if scene != "press":  # the press scene's button does not move in the plane
        assert np.ptp(fresh[:, 0]) > 0.02  # the object moved: a rollout with contacts


def test_objects_keep_their_ids_and_properties_across_resets() -> None:
    with make_scene("press", seed=0, context_source="ground_truth") as scene:
        ids = dict(scene._bodies.ids)
        scene.perturb("remove_object", name="box")
        scene.reset()
        assert scene._bodies.ids == ids  # rebuilt bodies reuse their ids
        assert "box" in scene.ground_truth()["objects"]  # a removed object comes back
        assert scene.button_depth() == pytest.approx(0.0, abs=1e-9)


def test_same_rollout_after_perturbations_and_gripper_actions() -> None:
    """A history with every kind of perturbation and the gripper closed and opened."""
    with make_scene("push", seed=0, object_jitter=0.0, context_source="ground_truth") as scene:
        home = np.asarray(scene.ground_truth()["objects"]["box"])
        _begin(scene, home, (-0.13, 0.0, 0.0))
        scene.close_gripper()
        scene.execute((1, 0, 0))
        scene.perturb("move_object", delta=(0.03, 0.02))
        scene.execute((1, 0, 0))
        scene.perturb("hold", steps=1)
        scene.execute((1, 0, 0))
        scene.perturb("remove_object")
        scene.execute((0, 1, 0))
        scene.open_gripper()
        _begin(scene, home, (-0.13, 0.0, 0.0))
        rows = [(*scene.ground_truth()["objects"]["box"], *scene.eef_position())]
        for d in ROLLOUT:
            scene.execute(d)
            rows.append((*scene.ground_truth()["objects"]["box"], *scene.eef_position()))
    assert np.array_equal(np.asarray(rows), _rollout("push", None))


#: Displacements off the axes (a DS step's), for :func:`test_first_episode_of_a_scene_...`.
DS_STEPS = [(0.031, -0.017, 0.005), (0.02, 0.02, -0.01), (0.04, 0.0, 0.0), (0.01, -0.03, 0.01),
            (0.035, 0.012, 0.0), (0.028, -0.021, 0.0)]


def _ds_rollout(scene: BulletScene, home: np.ndarray) -> np.ndarray:
    name = scene.primary_object
    _begin(scene, home, (-0.13, 0.01, 0.0))
    rows = [(*scene.ground_truth()["objects"][name], *scene.eef_position())]
    for d in DS_STEPS:
        scene.execute_displacement(d)
        rows.append((*scene.ground_truth()["objects"][name], *scene.eef_position()))
    return np.asarray(rows)


@pytest.mark.parametrize("scene_name", ["push", "press"])
def test_first_episode_of_a_scene_is_an_episode_like_the_others(scene_name: str) -> None:
    """Off-axis displacements (a DS run) from the first start of a new scene, after other
    episodes, and in a scene made after another one was closed in this process (a worker
    switching scenes) end bitwise at the same positions."""
    kw = {"seed": 0, "object_jitter": 0.0, "context_source": "ground_truth"}
    with make_scene(scene_name, **kw) as scene:
        home = np.asarray(scene.ground_truth()["objects"][scene.primary_object])
        first = _ds_rollout(scene, home)
        for offset, moves in HISTORIES["table"]:
            _begin(scene, home, offset)
            for d in moves:
                scene.execute(d)
        after = _ds_rollout(scene, home)
    with make_scene("grasp", **kw) as other:
        other.execute((0, 0, -1))
    with make_scene(scene_name, **kw) as scene:
        remade = _ds_rollout(scene, home)
    assert np.array_equal(after, first), np.abs(after - first).max()
    assert np.array_equal(remade, first), np.abs(remade - first).max()
    if scene_name == "push":
        assert np.ptp(first[:, 0]) > 0.01  # the box was pushed: contacts in the rollout
