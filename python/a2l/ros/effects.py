"""The effect tests of the skill node, from what its topics say (``docs/ros.md``).

The node has no simulator to ask: it tests a skill's effect from the object's pose, the
end-effector (forward kinematics of the joint states) and the high-level states, as the
scenes' detector (:func:`a2l.sim.observation.observed_effect`) does from the ground truth:

- a push (``left``, ``right``, ``close``, ``far``): the C++ core's push test on the object's
  displacement since the first tick (:func:`a2l.rollout.effect_tests.push_test`);
- ``grasped``: the object more than :data:`LIFT_THRESHOLD` (the C++ core's, 5 cm) above
  where it was at the first tick, the gripper ``closed`` (``states/gripper``) and the object
  within :data:`HOLD_RADIUS` of the end-effector;
- ``pressed``: the light (``states/light``) other than at the first tick (the button
  toggled it).

Each test reads the states it names (:attr:`NodeEffect.states`): the node subscribes to them
besides the bundle's own high-level states.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from a2l import _core
from a2l.errors import A2LValueError
from a2l.rollout.effect_tests import EffectTest, Progress, effect_test_of
from a2l.skills.effects import AXIS_EFFECTS

__all__ = ["HOLD_RADIUS", "LIFT_THRESHOLD", "NODE_EFFECTS", "NodeEffect", "bundle_effect",
           "node_effect"]

#: ``grasped``: the rise of the object (m), as the grasp scenes count it.
LIFT_THRESHOLD: float = _core.LIFT_THRESHOLD
#: ``grasped``: the object this close to the end-effector (m), as the scenes' detector.
HOLD_RADIUS = 0.08


@dataclass(frozen=True)
class NodeEffect:
    """An effect the skill node tests.

    Attributes
    ----------
    effect : str
        Its name.
    test : callable ``Progress -> (done, success)``
        The test (:data:`a2l.rollout.effect_tests.EffectTest`), reading no scene.
    states : tuple of str
        The high-level states it reads (their topics ``states/<name>``).
    """

    effect: str
    test: EffectTest
    states: tuple[str, ...] = ()


def _grasped(pr: Progress) -> tuple[bool, bool]:
    obj, start, eef = (np.asarray(v, dtype=float) for v in (pr.obj, pr.start_object, pr.eef))
    ok = bool(obj[2] - start[2] > LIFT_THRESHOLD and pr.states.get("gripper") == "closed"
              and np.linalg.norm(obj - eef) < HOLD_RADIUS)
    return ok, ok


def _pressed(pr: Progress) -> tuple[bool, bool]:
    ok = "light" in pr.start_states and pr.states.get("light") != pr.start_states["light"]
    return ok, ok


#: The effects the node tests beside the pushes: name -> (test, states it reads).
NODE_EFFECTS: dict[str, NodeEffect] = {
    "grasped": NodeEffect("grasped", _grasped, ("gripper",)),
    "pressed": NodeEffect("pressed", _pressed, ("light",)),
}


def node_effect(effect: str) -> NodeEffect:
    """The node's test of `effect`.

    Raises
    ------
    a2l.A2LValueError
        An effect the node cannot tell from its topics (the known ones named).
    """
    push = effect_test_of(effect) if effect in AXIS_EFFECTS else None
    if push is not None:
        return NodeEffect(effect, push)
    if effect in NODE_EFFECTS:
        return NODE_EFFECTS[effect]
    raise A2LValueError(f"effect {effect!r}: the ROS node tests the effects "
                        f"{', '.join([*AXIS_EFFECTS, *NODE_EFFECTS])} from its topics (run "
                        "others with a2l skill run)")


def bundle_effect(effects: Sequence[str], effect: str) -> NodeEffect:
    """The node's test of `effect`, one of a bundle's `effects` (its effect variable's
    values).

    Raises
    ------
    a2l.A2LValueError
        `effect` is not one of `effects` (they are listed), or the node cannot test it
        (:func:`node_effect`).
    """
    if effect not in effects:
        raise A2LValueError(f"effect {effect!r} is not one of the bundle's: "
                            f"{', '.join(effects)}")
    return node_effect(effect)
