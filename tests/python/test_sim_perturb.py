"""Perturbations: each one changes what the context reader returns at the next step."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest

from a2l.sim import make_scene
from a2l.sim.bullet import PressScene, PushScene


@pytest.fixture(scope="module")
def push() -> Iterator[PushScene]:
    with make_scene("push") as scene:  # perceived context, the experiments' default
        yield scene  # type: ignore[misc]


def _start(scene: PushScene) -> np.ndarray:
    scene.reset()
    box = np.asarray(scene.ground_truth()["objects"]["box"])
    scene.reset(eef=box + [-0.2, 0.0, -0.01])
    return box


def test_context_reader_low_level_state(push: PushScene) -> None:
    box = _start(push)
    ctx = push.context()
    assert ctx.source == "perceived"
    obj = ctx.objects["box"]
    eef = push.eef_position()
    assert np.allclose(ctx.eef, eef)
    assert np.allclose(obj.vector, obj.position - eef)
    assert np.allclose(obj.position, box, atol=0.005)  # perception error
    assert obj.distance == pytest.approx(np.linalg.norm(box - eef), abs=0.005)
    # the end-effector is in front of the box (-x): orientation of (eef - box) is ~pi,
    # slightly below the box centre: inclination a bit more than pi/2
    assert abs(abs(obj.orientation) - np.pi) < 0.05
    assert np.pi / 2 < obj.inclination < np.pi / 2 + 0.1
    truth = push.context(source="ground_truth")
    assert np.allclose(truth.objects["box"].position, box)


def test_move_object_changes_the_next_context(push: PushScene) -> None:
    box0 = _start(push)
    before = push.context()
    delta = np.array([0.05, -0.03, 0.0])
    push.perturb("move_object", delta=tuple(delta[:2]))
    after = push.context()
    assert np.allclose(after.objects["box"].vector - before.objects["box"].vector, delta,
                       atol=0.004)
    # independently of perception: the simulator's box moved by delta
    moved_box = np.asarray(push.ground_truth()["objects"]["box"])
    assert np.allclose(moved_box, box0 + delta, atol=1e-3)
    # and the next movement starts from there: after 5 cm in +x (which does not reach the
    # box), the context is read relative to the moved box, not the old one
    eef0 = push.eef_position()
    assert push.execute((1, 0, 0))
    now = push.context()
    eef1 = eef0 + [push.step_length, 0.0, 0.0]
    assert np.allclose(now.eef, eef1, atol=0.01)
    assert np.allclose(push.ground_truth()["objects"]["box"], moved_box, atol=1e-3)
    expected = np.linalg.norm(box0 + delta - eef1)          # 0.20 m
    unperturbed = np.linalg.norm(box0 - eef1)               # 0.15 m
    assert now.objects["box"].distance == pytest.approx(expected, abs=0.006)
    assert abs(now.objects["box"].distance - unperturbed) > 0.04


def test_hold_keeps_the_end_effector_still(push: PushScene) -> None:
    _start(push)
    push.perturb("hold", steps=2)
    here = push.eef_position()
    for _ in range(2):
        result = push.execute((1, 0, 0))
        assert not result and result.status == "held"
        assert np.allclose(push.context().eef, here, atol=0.002)
    moved = push.execute((1, 0, 0))
    assert moved
    assert push.context().eef[0] - here[0] == pytest.approx(push.step_length, abs=0.01)


def test_remove_object_empties_the_context(push: PushScene) -> None:
    _start(push)
    assert "box" in push.context().objects
    push.perturb("remove_object")
    assert "box" not in push.context().objects
    assert "box" not in push.perceive()["objects"]
    assert "box" not in push.ground_truth()["objects"]
    push.reset()
    assert "box" in push.context().objects


def test_toggle_gripper_changes_the_high_level_state(push: PushScene) -> None:
    _start(push)
    assert push.context().states["gripper"] == "open"
    push.perturb("toggle", state="gripper")
    assert push.context().states["gripper"] == "closed"


def test_toggle_light_is_seen_by_the_camera() -> None:
    with make_scene("press") as scene:
        scene.reset()
        assert scene.context().states["light"] == "off"
        scene.perturb("toggle", state="light")
        assert scene.context().states["light"] == "on"  # read from the pixels
        assert isinstance(scene, PressScene) and scene.presses == 0  # not a press


def test_bad_perturbations_are_named(push: PushScene) -> None:
    push.reset()
    with pytest.raises(ValueError, match="unknown perturbation kind 'earthquake'"):
        push.perturb("earthquake")
    with pytest.raises(ValueError, match="unknown high-level state 'light'"):
        push.perturb("toggle", state="light")
    with pytest.raises(ValueError, match="unknown object 'cup'"):
        push.perturb("move_object", delta=(0.01, 0.0), name="cup")
    with pytest.raises(ValueError, match="unknown parameter 'force'"):
        push.perturb("hold", steps=1, force=3)
    with pytest.raises(ValueError, match="off the table"):
        push.perturb("move_object", delta=(2.0, 0.0))
    with pytest.raises(ValueError, match="steps"):
        push.perturb("hold", steps=-1)


def test_bad_reset_leaves_the_scene_as_it_was(push: PushScene) -> None:
    _start(push)
    assert push.execute((1, 0, 0))
    eef, truth = push.eef_position(), push.ground_truth()
    with pytest.raises(ValueError, match="unreachable"):
        push.reset(eef=(2.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="unknown object 'cup'"):
        push.reset(objects={"cup": (0.6, 0.0)})
    with pytest.raises(ValueError, match="off the table"):
        push.reset(objects={"box": (0.0, 0.0)})
    assert np.allclose(push.eef_position(), eef)
    assert push.ground_truth() == truth
