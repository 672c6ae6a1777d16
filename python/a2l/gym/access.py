"""What a2l needs to read and place in a Gymnasium environment to drive it as a scene: the
end-effector, the object, the goal (:class:`EnvAccess`), and the one implementation for
panda-gym's tasks (:class:`PandaGymAccess`).

:func:`env_access` finds it for an environment, or refuses the environment with an error
naming what it lacks: a Gymnasium environment is a black box of observations and actions,
and a2l's skills read where the end-effector and the object are.
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from a2l.errors import A2LValueError

__all__ = ["EnvAccess", "PandaGymAccess", "env_access"]

#: The gripper pointing down, as panda-gym's end-effector control keeps it (x, y, z, w).
_DOWN = np.array([1.0, 0.0, 0.0, 0.0])
#: Rounds of inverse kinematics when the arm is placed (each from the last solution).
_IK_ROUNDS = 12


class EnvAccess(Protocol):
    """Reads and places what a2l's scene protocol needs, in one Gymnasium environment."""

    #: The objects a push can move, by name.
    object_names: tuple[str, ...]

    def ee_position(self) -> NDArray[np.float64]:
        """End-effector point in the world frame (m), shape (3,)."""
        ...

    def object_position(self, name: str) -> NDArray[np.float64]:
        """Centre of object `name` (m), shape (3,)."""
        ...

    def place_object(self, name: str, xyz: NDArray[np.float64]) -> None:
        """Put object `name` at `xyz` (3,), upright and at rest."""
        ...

    def place_ee(self, xyz: NDArray[np.float64]) -> float:
        """Put the arm (kinematically, no simulated time) with its end-effector at `xyz`
        (3,), as the environment's own reset puts it at its neutral pose; returns the
        distance left to `xyz` (m)."""
        ...

    def goal(self) -> NDArray[np.float64] | None:
        """The episode's goal position (3,), or None when the task has none."""
        ...


class PandaGymAccess:
    """panda-gym's tasks (``PandaPush-v3``, ``PandaSlide-v3``, ``PandaPickAndPlace-v3``...):
    ``robot.get_ee_position()``, ``sim.get_base_position("object")``,
    ``sim.set_base_pose``, ``robot.inverse_kinematics`` and ``robot.set_joint_angles``, the
    task's ``goal``.

    Parameters
    ----------
    env : gymnasium.Env
        A panda-gym environment (wrapped or not).
    """

    object_names = ("object",)

    def __init__(self, env: Any) -> None:
        core = env.unwrapped
        self.robot, self.sim, self.task = core.robot, core.sim, core.task

    def ee_position(self) -> NDArray[np.float64]:
        return np.asarray(self.robot.get_ee_position(), dtype=float).copy()

    def object_position(self, name: str) -> NDArray[np.float64]:
        return np.asarray(self.sim.get_base_position(name), dtype=float).copy()

    def place_object(self, name: str, xyz: NDArray[np.float64]) -> None:
        # set_base_pose leaves the body at rest (velocities zero)
        self.sim.set_base_pose(name, np.asarray(xyz, dtype=float), np.array([0.0, 0, 0, 1]))

    def place_ee(self, xyz: NDArray[np.float64]) -> float:
        target = np.asarray(xyz, dtype=float)
        err = np.inf
        for _ in range(_IK_ROUNDS):  # pybullet's IK starts from the current joints
            angles = self.robot.inverse_kinematics(link=self.robot.ee_link, position=target,
                                                   orientation=_DOWN)
            self.robot.set_joint_angles(angles)
            err = float(np.linalg.norm(self.ee_position() - target))
            if err < 5e-4:
                break
        return err

    def goal(self) -> NDArray[np.float64] | None:
        goal = getattr(self.task, "goal", None)
        return None if goal is None else np.asarray(goal, dtype=float).copy()


def _describe(env: Any) -> str:
    spec = getattr(env, "spec", None)
    return repr(spec.id) if spec is not None else type(env).__name__


def env_access(env: Any) -> PandaGymAccess:
    """The access to `env`'s end-effector, object and goal.

    Raises
    ------
    a2l.A2LValueError
        `env` exposes no end-effector or no object the way a2l knows (the message names
        what is missing and what a2l reads).
    """
    core = getattr(env, "unwrapped", env)
    robot, sim = getattr(core, "robot", None), getattr(core, "sim", None)
    missing = []
    if robot is None or not callable(getattr(robot, "get_ee_position", None)):
        missing.append("an end-effector (unwrapped.robot.get_ee_position())")
    if sim is None or not callable(getattr(sim, "get_base_position", None)):
        missing.append("an object (unwrapped.sim.get_base_position('object'))")
    elif not _has_body(sim, "object"):
        missing.append("a body named 'object' in its simulation")
    if missing:
        raise A2LValueError(
            f"Gymnasium environment {_describe(env)} does not expose " + " nor ".join(missing)
            + ": a2l drives an environment as a scene only where it can read the "
            "end-effector and the object (panda-gym's tasks: PandaPush-v3, PandaSlide-v3, "
            "PandaPickAndPlace-v3...); for another environment, give GymScene an access "
            "object (a2l.gym.EnvAccess)")
    return PandaGymAccess(env)


def _has_body(sim: Any, name: str) -> bool:
    try:
        sim.get_base_position(name)
    except (KeyError, AttributeError):
        return False
    return True
