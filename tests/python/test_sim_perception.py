"""Camera perception against ground truth."""

from __future__ import annotations

import numpy as np

from a2l.sim import make_scene
from a2l.sim.perception import perception_errors


def test_perception_error_over_200_random_positions() -> None:
    with make_scene("push") as scene:
        positions, errors = perception_errors(scene, 200, seed=0)
    assert not np.isnan(errors).any()  # the camera sees the whole table
    cfg = scene.config
    assert np.ptp(positions[:, 0]) > 0.5 * cfg.table_size[0]  # spread over the table
    assert np.ptp(positions[:, 1]) > 0.5 * cfg.table_size[1]
    err = np.linalg.norm(errors, axis=1)
    print(f"perception error over 200 positions: median {np.median(err) * 1000:.2f} mm, "
          f"max {err.max() * 1000:.2f} mm")
    # the error budget of the default resolution (256 x 192, scene_config.py): 95 % of reads
    # within half the 1 cm effect threshold; these 200 positions, seed 0: median 1.48 mm,
    # p95 3.80 mm, max 5.14 mm (docs/tabletop.md)
    assert np.median(err) <= 0.002
    assert np.percentile(err, 95) <= 0.5 * scene.config.effect_threshold
    assert err.max() <= 0.006


def test_perceives_every_object_and_the_light() -> None:
    with make_scene("press", states={"light": "on"}) as scene:
        truth = scene.ground_truth()
        seen = scene.perceive()
        assert set(seen["objects"]) == set(truth["objects"]) == {"box", "button"}
        for name, pos in truth["objects"].items():
            assert np.linalg.norm(np.subtract(seen["objects"][name], pos)) < 0.005
        assert seen["states"]["light"] == "on"
    with make_scene("grasp") as scene:
        truth = scene.ground_truth()["objects"]["block"]
        seen = scene.perceive()["objects"]["block"]
        assert np.linalg.norm(np.subtract(seen, truth)) < 0.005


def test_rendering_with_collision_shapes_changes_the_robot_not_the_result() -> None:
    with make_scene("push", robot_visual="mesh") as scene:
        rgb, depth = scene.render()
        assert rgb.shape == (scene.config.camera_height, scene.config.camera_width, 3)
        assert depth.shape == rgb.shape[:2]
        truth = np.asarray(scene.ground_truth()["objects"]["box"])
        seen = np.asarray(scene.perceive()["objects"]["box"])
        assert np.linalg.norm(seen - truth) < 0.005


def test_perception_while_the_arm_hides_the_box_from_the_main_camera() -> None:
    # pushing the box toward the robot puts the gripper between the main camera and the
    # box: perception must complete the clipped top face with the other views (the points
    # of every view rendered, joined) instead of returning a clipped box
    with make_scene("push") as scene:
        box = np.asarray(scene.ground_truth()["objects"]["box"])
        for direction in [(-1, 0), (-1, -1)]:
            u = np.array([*direction, 0.0]) / np.hypot(*direction)
            scene.reset(eef=box - 0.14 * u + [0, 0, -0.01])
            for _ in range(4):
                assert scene.execute((*direction, 0))
                rgb, depth = scene.render(0)
                _, _, visible = scene.perception.locate(rgb, depth)
                truth = np.asarray(scene.ground_truth()["objects"]["box"])
                seen = np.asarray(scene.perceive()["objects"]["box"])
                # <= 6.0 mm measured with the views joined; the best single view (the
                # rule before) was 10.8 mm off after the fourth diagonal push, the box 46 %
                # visible in the main camera
                assert np.linalg.norm(seen - truth) < 0.007, (direction, visible)
            assert visible.get("box", 0.0) < scene.config.min_visible  # it was hidden
