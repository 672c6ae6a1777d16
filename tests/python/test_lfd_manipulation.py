"""Manipulation scenes (grasp, press, grasp_light), their effect tests, and the scripted
demonstrators: the demonstrations have the promised shape and reproduce their effect when
replayed on Baxter in PyBullet."""

from __future__ import annotations

import numpy as np
import pytest

from a2l.errors import A2LValueError
from a2l.lfd import Demonstration, load_demonstrations, save_demonstrations
from a2l.lfd.manipulation import (
    GRASP_POINT,
    LIFT,
    PRESS_POINT,
    RETREAT,
    SKILL_OBJECTS,
    demonstrate,
    grasp_light_demonstration,
    replay,
    segment_actions,
)
from a2l.rollout.effect_tests import AWAY_RADIUS, scene_outcome, stayed_away
from a2l.sim import make_scene


def test_grasp_light_scene_has_a_lamp_the_camera_sees() -> None:
    with make_scene("grasp_light") as scene:  # perceived: the light comes from the pixels
        assert set(scene.state_names) == {"gripper", "light"}
        assert scene.object_names == ("block",)
        assert scene.perceive()["states"]["light"] == "off"
        scene.perturb("toggle", state="light")
        assert scene.perceive()["states"]["light"] == "on"
        assert scene.ground_truth()["states"]["light"] == "on"
        # the light is not the robot's doing in this scene: no "pressed" effect
        assert scene.observe_effect(since="episode") == "none"
        scene.reset()
        assert scene.ground_truth()["states"]["light"] == "off"
    with make_scene("grasp_light", states={"light": "on"},
                    context_source="ground_truth") as scene:
        assert scene.context().states == {"gripper": "open", "light": "on"}
    with pytest.raises(A2LValueError, match="lamp_position"):
        make_scene("grasp_light", lamp_position=(3.0, 0.0))


def test_grasped_needs_five_centimetres_up_in_the_closed_gripper() -> None:
    with make_scene("grasp", context_source="ground_truth") as scene:
        assert scene.config.lift_threshold == pytest.approx(0.05)
        block = np.asarray(scene.ground_truth()["objects"]["block"])
        scene.reset(eef=block + GRASP_POINT + [0, 0, 0.05])
        assert scene.execute((0, 0, -1))
        scene.close_gripper()
        test = scene_outcome("grasped")
        assert not test(scene)
        # 3 cm up: in the gripper, not high enough
        scene.config.step = 0.03
        assert scene.execute((0, 0, 1))
        assert not test(scene)
        scene.config.step = 0.05
        assert scene.execute((0, 0, 1))
        lifted = np.asarray(scene.ground_truth()["objects"]["block"])
        assert lifted[2] - block[2] >= 0.05
        assert test(scene)
    with pytest.raises(A2LValueError, match="no effect test"):
        scene_outcome("flown")


def test_demonstrations_are_seeded_segments_in_the_object_frame() -> None:
    a, b = demonstrate("grasp", 2, seed=3)
    again = demonstrate("grasp", 1, seed=3)[0]
    assert all(np.array_equal(x.positions, y.positions) for x, y in zip(a, again, strict=True))
    assert not np.allclose(a[0].positions[0], b[0].positions[0])
    reach, lift = a
    assert reach.frame == lift.frame == "object" and reach.dim == 3
    assert reach.states == {"gripper": "open"} and lift.states == {"gripper": "closed"}
    assert np.allclose(reach.positions[-1], GRASP_POINT)
    assert np.allclose(lift.positions[-1] - lift.positions[0], [0, 0, LIFT])
    # approach from above: the last 5 cm straight down onto the grasp point
    last = reach.positions[reach.positions[:, 2] < GRASP_POINT[2] + 0.05]
    assert np.allclose(last[:, :2], reach.positions[-1, :2], atol=0.01)
    assert segment_actions(a) == ["close", None]
    (press,) = demonstrate("press", 1, seed=0)[0]
    assert np.allclose(press.positions[-1], PRESS_POINT) and press.states == {}
    off, on = demonstrate("grasp_light", 2, seed=0)
    assert [s.states for s in off] == [{"light": "off", "gripper": "open"},
                                       {"light": "off", "gripper": "closed"}]
    (away,) = on
    assert away.states == {"light": "on"}
    assert np.linalg.norm(away.positions[-1] - RETREAT) < AWAY_RADIUS / 2
    assert np.linalg.norm(away.positions[-1]) > 0.15
    # waits: the last second at the same place
    assert away.times[-1] - away.times[-6] == pytest.approx(1.0)
    assert np.allclose(away.positions[-6:], away.positions[-1])
    with pytest.raises(A2LValueError, match="light"):
        grasp_light_demonstration(0, "dim")
    with pytest.raises(A2LValueError, match="unknown manipulation skill"):
        demonstrate("juggle", 1)


def test_demonstrations_round_trip_through_the_file_format(tmp_path) -> None:
    segments = [s for demo in demonstrate("grasp_light", 2, seed=5) for s in demo]
    path = save_demonstrations(tmp_path / "demos.csv", segments)
    loaded = load_demonstrations(path)
    assert len(loaded) == 3
    for x, y in zip(segments, loaded, strict=True):
        assert isinstance(y, Demonstration)
        assert np.allclose(x.positions, y.positions) and x.states == y.states


@pytest.mark.parametrize("skill", ["grasp", "press", "grasp_light"])
def test_replayed_demonstrations_produce_their_effect(skill: str) -> None:
    obj = SKILL_OBJECTS[skill]
    with make_scene(skill, context_source="ground_truth", object_jitter=0.03,
                    seed=11) as scene:
        for demo in demonstrate(skill, 2 if skill != "grasp_light" else 4, seed=20):
            light = demo[0].states.get("light", "off")
            assert replay(scene, demo, obj)
            wanted = {"grasp": "grasped", "press": "pressed"}.get(
                skill, "grasped" if light == "off" else "away")
            assert scene_outcome(wanted)(scene), (skill, light, scene.ground_truth())
            if wanted == "away":
                assert scene.ground_truth()["states"]["light"] == "on"
                assert not scene_outcome("grasped")(scene)
            if wanted == "grasped":
                assert not stayed_away(scene)


def test_the_light_on_behaviour_is_not_a_grasp_and_a_grasp_is_not_away() -> None:
    with make_scene("grasp_light", context_source="ground_truth") as scene:
        # the light-off demonstration replayed with the gripper never closing: no grasp
        reach, lift = demonstrate("grasp_light", 1, seed=2)[0]
        replay(scene, [reach, Demonstration(lift.positions, lift.times, "object",
                                            {"light": "off", "gripper": "open"})], "block")
        assert not scene_outcome("grasped")(scene)
        # staying next to the block is not "away"
        assert not stayed_away(scene)
        # at the retreat pose with the block knocked over is not "away" either
        scene.reset()
        block = np.asarray(scene.ground_truth()["objects"]["block"])
        scene.reset(eef=block + RETREAT)
        assert stayed_away(scene)
        scene.perturb("move_object", delta=(0.02, 0.0))
        assert not stayed_away(scene)
