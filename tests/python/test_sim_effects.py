"""Effects: the detector alone, then scripted movements in PyBullet that produce each effect
(push in 8 directions, grasp, press) and the detector naming it."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest

from a2l.sim import make_scene
from a2l.sim.bullet import PushScene
from a2l.skills.effects import EFFECT_NAMES, effect_name
from a2l.skills.repertoire import default_directions


def test_directions_are_the_26_sign_vectors() -> None:
    DIRECTIONS = [tuple(int(s) for s in d) for d in default_directions()]
    assert len(DIRECTIONS) == 26
    assert len(set(DIRECTIONS)) == 26
    assert all(set(d) <= {-1, 0, 1} and d != (0, 0, 0) for d in DIRECTIONS)


@pytest.mark.parametrize(
    ("d", "n", "name"),
    [
        ((0.05, 0.0), 8, "far"), ((-0.05, 0.01), 8, "close"), ((0.0, 0.03), 8, "left"),
        ((0.01, -0.05), 8, "right"), ((0.04, 0.02), 8, "far_left"),
        ((0.04, -0.02), 8, "far_right"), ((-0.03, 0.03), 8, "close_left"),
        ((-0.02, -0.04), 8, "close_right"), ((0.04, 0.02), 4, "far"),
        ((-0.02, -0.04), 4, "right"), ((0.005, 0.005), 8, "none"), ((0.0, 0.0, 0.2), 8, "none"),
    ],
)
def test_effect_names(d: tuple, n: int, name: str) -> None:
    assert effect_name(d, n_effects=n) == name


def test_effect_name_ratio_boundary() -> None:
    # docs/method.md: an axis effect only when the dominant axis moved more than 3x the other
    assert effect_name((0.031, 0.01)) == "far"
    assert effect_name((0.029, 0.01)) == "far_left"
    with pytest.raises(ValueError):
        effect_name((np.nan, 0.0))


@pytest.fixture(scope="module")
def push() -> Iterator[PushScene]:
    with make_scene("push", context_source="ground_truth") as scene:
        yield scene  # type: ignore[misc]


_PUSHES = {
    (1, 0): "far", (-1, 0): "close", (0, 1): "left", (0, -1): "right",
    (1, 1): "far_left", (1, -1): "far_right", (-1, 1): "close_left", (-1, -1): "close_right",
}


@pytest.mark.parametrize(("direction", "effect"), list(_PUSHES.items()))
def test_scripted_push_produces_each_effect(push: PushScene, direction: tuple[int, int],
                                           effect: str) -> None:
    push.reset()
    box = np.asarray(push.ground_truth()["objects"]["box"])
    u = np.array([*direction, 0.0]) / np.hypot(*direction)
    push.reset(eef=box - 0.14 * u + [0, 0, -0.01])
    before = push.context()
    assert before.objects["box"].distance == pytest.approx(np.hypot(0.14, 0.01), abs=0.005)
    step_effects = []
    for _ in range(4):
        result = push.execute((*direction, 0))
        assert result, result.message
        step_effects.append(push.observe_effect())
    assert step_effects[0] == "none"  # the first step does not reach the box
    assert push.observe_effect(since="episode") == effect
    assert effect in step_effects
    moved = np.asarray(push.ground_truth()["objects"]["box"]) - box
    assert np.hypot(*moved[:2]) > 0.03
    assert effect in EFFECT_NAMES


def test_movement_lengths_and_straightness(push: PushScene) -> None:
    push.reset(eef=(0.5, -0.45, -0.1))
    for d in [(0, 0, 1), (1, 1, 1), (-1, 0, -1), (0, -1, 0)]:
        start = push.eef_position()
        result = push.execute(d)
        assert result, result.message
        expected = start + push.step_length * np.asarray(d) / np.linalg.norm(d)
        assert np.linalg.norm(result.reached - expected) < push.config.reach_tolerance
        assert np.allclose(result.target, expected)


def test_workspace_limit_is_reported_and_nothing_moves(push: PushScene) -> None:
    push.reset(eef=(0.6, -0.3, push.config.table_z + 0.03))
    start = push.eef_position()
    down = push.execute((0, 0, -1))  # below the table-top clearance
    assert not down and down.status == "workspace_limit"
    assert "along z" in down.message
    assert np.allclose(push.eef_position(), start, atol=1e-4)
    with pytest.raises(ValueError, match="movement"):
        push.execute((2, 0, 0))
    with pytest.raises(ValueError, match="movement"):
        push.execute((0, 0, 0))


def test_unreachable_is_reported_not_replaced() -> None:
    # wide workspace bounds: the IK, not the bounds, meets the edge of Baxter's reach
    with make_scene("push", workspace_max=(1.5, 0.45, 0.45),
                    context_source="ground_truth") as scene:
        scene.reset(eef=(0.75, -0.3, -0.1))
        results = [scene.execute((1, 0, 0)) for _ in range(5)]
        failed = [r for r in results if not r]
        assert failed, [r.reached for r in results]
        first = failed[0]
        assert first.status == "unreachable" and "IK" in first.message
        # never replaced by another motion: the end-effector stays where it was
        assert np.allclose(scene.eef_position(), first.reached, atol=0.002)
        assert scene.eef_position()[0] < first.target[0] - 0.03


def test_scripted_grasp_is_named_grasped() -> None:
    with make_scene("grasp", context_source="ground_truth") as scene:
        scene.reset()
        block = np.asarray(scene.ground_truth()["objects"]["block"])
        scene.reset(eef=block + [0, 0, 0.09])
        assert scene.execute((0, 0, -1)) and scene.execute((0, 0, -1))
        assert scene.observe_effect() == "none"
        scene.close_gripper()
        assert scene.context().states["gripper"] == "closed"
        assert scene.contacts("block")
        assert scene.execute((0, 0, 1))
        # one 5 cm step up: the block rises a little less (it settles in the fingers);
        # grasped needs lift_threshold = 5 cm
        assert scene.observe_effect() == "none"
        assert scene.execute((0, 0, 1))
        lifted = np.asarray(scene.ground_truth()["objects"]["block"])
        assert lifted[2] - block[2] > 0.08
        assert scene.observe_effect(since="episode") == "grasped"
        # with the gripper open the same movements lift nothing
        scene.reset(eef=block + [0, 0, 0.09])
        for d in [(0, 0, -1), (0, 0, -1), (0, 0, 1), (0, 0, 1)]:
            assert scene.execute(d)
        assert scene.observe_effect(since="episode") == "none"


def test_scripted_press_is_named_pressed_and_toggles_the_light() -> None:
    with make_scene("press") as scene:  # perceived: the light state comes from the pixels
        button = np.asarray(scene.ground_truth()["objects"]["button"])
        scene.reset(eef=button + [0, 0, 0.04])
        assert scene.context().states["light"] == "off"
        assert scene.execute((0, 0, -1))
        assert scene.observe_effect() == "pressed"
        assert scene.perceive()["states"]["light"] == "on"
        assert scene.ground_truth()["states"]["light"] == "on"
        assert scene.execute((0, 0, 1))
        assert scene.observe_effect() == "none"  # releasing does not toggle
        assert scene.execute((0, 0, -1))
        assert scene.observe_effect() == "pressed"
        assert scene.perceive()["states"]["light"] == "off"
        assert scene.presses == 2
        # hovering above the button without reaching it presses nothing
        scene.reset(eef=button + [0, 0, 0.15])
        assert scene.execute((0, 0, -1))
        assert scene.observe_effect() == "none"
        assert scene.presses == 0
