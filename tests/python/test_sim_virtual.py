"""The virtual scene: the C++ push model behind the Scene interface."""

from __future__ import annotations

import numpy as np
import pytest

from a2l import _core
from a2l.sim import make_scene


def test_wraps_the_cpp_model() -> None:
    with make_scene("virtual") as scene:
        assert isinstance(scene._model, _core.VirtualScene)  # no Python push model


def test_push_along_dominant_axis_and_effects() -> None:
    with make_scene("virtual") as scene:
        box0 = np.asarray(scene.ground_truth()["objects"]["box"])
        scene.reset(eef=box0 + [-0.1, 0.0, 0.0])
        assert scene.execute((1, 0, 0))
        assert scene.observe_effect() == "none"  # eef at -0.05: not yet in the box
        assert scene.execute((1, 0, 0))  # eef at the box centre: pushed to touch it
        box = np.asarray(scene.ground_truth()["objects"]["box"])
        half, r = scene.config.box_half_size[0], scene.config.eef_radius
        assert box[0] == pytest.approx(scene.eef_position()[0] + half + r)
        assert scene.observe_effect() == "far"
        ctx = scene.context()
        assert ctx.objects["box"].distance == pytest.approx(half + r)
        scene.perturb("move_object", delta=(0.0, 0.1))
        assert scene.context().objects["box"].vector[1] == pytest.approx(0.1)
        scene.perturb("remove_object")
        assert scene.context().objects == {}
        assert scene.execute((1, 0, 0))
        assert scene.observe_effect() == "none"


def test_vertical_moves_never_push() -> None:
    with make_scene("virtual") as scene:
        box0 = np.asarray(scene.ground_truth()["objects"]["box"])
        scene.reset(eef=box0 + [0.0, 0.0, 0.1])
        for _ in range(3):
            scene.execute((0, 0, -1))
        assert np.allclose(scene.ground_truth()["objects"]["box"], box0)
        assert scene.observe_effect(since="episode") == "none"
