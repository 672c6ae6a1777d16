"""The gripper's turn about the vertical (``SceneConfig.gripper_yaw``): validated, obeyed by
every reset and movement, and set by the sideways push skills' recipes (their
fingers close along x, so they lie side by side on the face a push across y meets)."""

from __future__ import annotations

import numpy as np
import pytest

from a2l.errors import A2LValueError
from a2l.lfd.library import SIDEWAYS_SCENE, make_skill_scene
from a2l.sim import make_scene


def _finger_gap(scene) -> np.ndarray:
    """Vector (3,) from the right finger tip to the left one of the acting arm."""
    poses = scene.link_poses()
    return poses["r_gripper_l_finger_tip"][0] - poses["r_gripper_r_finger_tip"][0]


@pytest.mark.parametrize("bad", [200.0, -181, "90", True, float("nan")])
def test_gripper_yaw_rejects_a_bad_value_naming_the_field(bad) -> None:
    with pytest.raises(A2LValueError, match="gripper_yaw"):
        make_scene("push", gripper_yaw=bad)


@pytest.mark.parametrize(("yaw", "axis"), [(0.0, 1), (90.0, 0)])
def test_fingers_close_along_the_axis_the_yaw_says_and_movements_keep_it(yaw, axis) -> None:
    with make_scene("push", seed=0, gripper_yaw=yaw, context_source="ground_truth") as scene:
        box = np.asarray(scene.ground_truth()["objects"]["box"])
        scene.reset(eef=box + np.array([0.0, 0.13, 0.0]))
        assert np.linalg.norm(scene.eef_position() - box - [0.0, 0.13, 0.0]) < 1e-3
        for d in [(1, 0, 0), (0, -1, 0)]:
            assert scene.execute(d)
            gap = _finger_gap(scene)
            assert abs(gap[axis]) > 0.05, gap  # open fingers, 7 cm apart
            assert np.all(np.abs(np.delete(gap, axis)) < 0.005), gap


def test_sideways_push_scenes_turn_the_gripper_and_the_others_do_not() -> None:
    assert SIDEWAYS_SCENE == {"gripper_yaw": 90.0}
    for skill, yaw in (("push_right", 90.0), ("push_left", 90.0), ("push_far", 0.0)):
        with make_skill_scene(skill, 0, scene="press") as scene:
            assert scene.config.gripper_yaw == yaw
    with make_skill_scene("push_right", 0, gripper_yaw=0.0) as scene:  # a caller overrides
        assert scene.config.gripper_yaw == 0.0
    with make_skill_scene("push_right", 0, scene="virtual") as scene:  # no gripper there
        assert not hasattr(scene.config, "gripper_yaw")
