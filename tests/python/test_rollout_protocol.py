"""The scenes implement the scene protocols of :mod:`a2l.rollout.protocol`, and the one
closed loop (:func:`a2l.rollout.loop.closed_loop`) keeps its order and its stop statuses."""

from __future__ import annotations

import inspect

import numpy as np
import pytest

from a2l.rollout import (
    ArmSceneProtocol,
    Decision,
    SceneProtocol,
    closed_loop,
    thread_scene,
)
from a2l.sim import make_scene
from a2l.sim.bullet import BulletScene
from a2l.sim.virtual import VirtualScene


def _members(proto: type) -> set[str]:
    names = {n for n, _ in inspect.getmembers(proto) if not n.startswith("_")}
    names |= set(getattr(proto, "__annotations__", {}))
    return names


@pytest.mark.parametrize(("cls", "proto"), [(VirtualScene, SceneProtocol),
                                            (BulletScene, ArmSceneProtocol)])
def test_the_scenes_have_every_member_of_their_protocol(cls: type, proto: type) -> None:
    missing = {n for n in _members(proto) - {"config", "seed", "kinematics", "robot_entry"}
               if not hasattr(cls, n)}
    assert not missing


def test_the_public_scene_methods_replace_the_private_ones() -> None:
    scene = make_scene("virtual", step=0.05)
    start = scene.episode_start()
    assert start == scene.ground_truth()
    res = scene.move_by([0.12, 0.0, 0.0])       # longer than a movement: any displacement
    assert res.carried_out and np.allclose(res.reached, res.target)
    assert scene.episode_start() == start
    assert scene.movable_names == ("box",)
    with pytest.raises(ValueError, match="finite"):
        scene.move_by([np.nan, 0.0, 0.0])


class _Line:
    """A world on a line: the object at x = 1 moves once the end-effector reaches it."""

    def __init__(self, wall: float = np.inf) -> None:
        self.x, self.obj, self.wall = 0.0, 1.0, wall

    def observe(self):
        return np.array([self.x, 0, 0.0]), np.array([self.obj, 0, 0.0]), {}

    def act(self, decision: Decision) -> str:
        if self.x + decision.command > self.wall:
            return "unreachable"
        self.x += decision.command
        if self.x >= self.obj:
            self.obj += 0.5
        return "ok"


def _forward(k: int, eef, obj, states) -> Decision:
    return Decision("ok", "forward", np.array([0.25, 0, 0]), 0.25, 0)


def _moved(k: int, eef, obj, states) -> str | None:
    return "moved" if obj[0] > 1.0 else None


def test_closed_loop_stops_on_the_effect_the_cap_the_policy_and_a_fatal_move() -> None:
    t = closed_loop(_Line(), _forward, _moved, cap=10)
    assert t.stop == "moved" and t.executed == 4 and len(t.eef) == 5
    assert [s.status for s in t.steps] == ["ok"] * 4 + ["moved"]
    assert closed_loop(_Line(), _forward, _moved, cap=2, cap_status="exhausted").stop \
        == "exhausted"
    t = closed_loop(_Line(), lambda *a: Decision("step_cap"), _moved, cap=10)
    assert t.stop == "step_cap" and t.executed == 0 and len(t.steps) == 1
    t = closed_loop(_Line(wall=0.6), _forward, _moved, cap=10)
    assert t.stop == "unreachable" and t.carried_out() == [0, 0]
    assert [s.move_status for s in t.steps] == ["ok", "ok", "unreachable", ""]
    assert len(t.eef) == 4                       # observed again after the fatal move


def test_thread_scene_keeps_one_scene_per_slot() -> None:
    closed: list[int] = []

    class S:
        def __init__(self, k: int) -> None:
            self.k = k

        def close(self) -> None:
            closed.append(self.k)

    a = thread_scene("test-slot", 1, lambda: S(1))
    assert thread_scene("test-slot", 1, lambda: S(9)) is a
    b = thread_scene("test-slot", 2, lambda: S(2))
    assert b.k == 2 and closed == [1]
