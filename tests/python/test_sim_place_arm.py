"""Putting the arm back kinematically (``BulletScene.place_arm``, the babbling experiment's
way back): the joints are those of a reset to the same end-effector position, nothing else
moves at the placement, the motors then hold the arm there, and an unreachable position
leaves the world as it was."""

from __future__ import annotations

import numpy as np
import pytest

from a2l.errors import A2LValueError
from a2l.sim import make_scene


def test_place_arm_puts_the_arm_where_a_reset_would_and_moves_nothing_else() -> None:
    with make_scene("push", seed=0, object_jitter=0.0,
                    context_source="ground_truth") as scene:
        box = np.asarray(scene.ground_truth()["objects"]["box"])
        start = box + np.array([-0.13, 0.0, 0.0])
        scene.reset(eef=start)
        q_reset = scene.joint_positions()
        for d in [(1, 0, 0)] * 3:  # push the box 5-10 cm
            assert scene.execute(d)
        pushed = np.asarray(scene.ground_truth()["objects"]["box"])
        assert pushed[0] - box[0] > 0.03
        scene.place_arm(start)
        assert np.array_equal(scene.joint_positions(), q_reset)
        assert np.linalg.norm(scene.eef_position() - start) < 1e-3
        assert np.array_equal(np.asarray(scene.ground_truth()["objects"]["box"]), pushed)
        scene.settle(0.3)  # the motors hold the arm where it was put
        assert np.linalg.norm(scene.eef_position() - start) < 3e-3
        # the box slides on a little where it was pushed, and nothing pulls it back
        rest = np.asarray(scene.ground_truth()["objects"]["box"])
        assert 0 <= rest[0] - pushed[0] < 0.03 and abs(rest[1] - pushed[1]) < 0.005

        q = scene.joint_positions()
        with pytest.raises(A2LValueError, match="place_arm: eef .* unreachable"):
            scene.place_arm(start + np.array([2.0, 0.0, 0.0]))
        with pytest.raises(A2LValueError, match="finite"):
            scene.place_arm([np.nan, 0.0, 0.0])
        assert np.array_equal(scene.joint_positions(), q)
