"""What the rooms above :mod:`a2l.sim` may ask of a scene: :class:`SceneProtocol` (every
scene: the virtual one and the PyBullet ones) and :class:`ArmSceneProtocol` (the PyBullet
scenes: an arm with a gripper, cameras, simulated time).

They are typing protocols: :class:`a2l.sim.Scene` and :class:`a2l.sim.bullet.BulletScene`
implement them without naming them. A module outside :mod:`a2l.sim` uses these methods
and nothing private of a scene (``tests/python/test_no_private_access.py`` checks it).
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from a2l.sim.context import Context
from a2l.sim.movement import MoveResult

__all__ = ["ArmSceneProtocol", "SceneProtocol"]


class SceneProtocol(Protocol):
    """A tabletop scene (:class:`a2l.sim.Scene`): positions in the world frame (m)."""

    #: Scene name (``"push"``, ``"virtual"``...).
    name: str
    #: The object perturbations act on by default.
    primary_object: str
    #: The scene's configuration (:class:`a2l.sim.SceneConfig`, :class:`a2l.sim.VirtualConfig`).
    config: Any
    #: The seed the scene was built with.
    seed: int

    def reset(self, eef: ArrayLike | None = None,
              objects: dict[str, ArrayLike] | None = None) -> None:
        """Initial state (end-effector and objects optionally placed); starts an episode."""
        ...

    def eef_position(self) -> NDArray[np.float64]:
        """End-effector point, shape (3,)."""
        ...

    def ground_truth(self) -> dict[str, dict[str, Any]]:
        """``{"objects": {name: (x, y, z)}, "states": {name: value}}``, true values."""
        ...

    def perceive(self) -> dict[str, dict[str, Any]]:
        """As :meth:`ground_truth`, as the cameras see it."""
        ...

    def episode_start(self, source: str = "ground_truth") -> dict[str, dict[str, Any]]:
        """As :meth:`ground_truth` (or :meth:`perceive`), at the start of the episode."""
        ...

    def start_episode(self) -> None:
        """Start a new effect episode now, without resetting anything."""
        ...

    def execute(self, movement: ArrayLike | str) -> MoveResult:
        """One discrete movement (signs in {-1, 0, 1}) or an action (``open``...)."""
        ...

    def execute_displacement(self, displacement: ArrayLike) -> MoveResult:
        """A displacement of at most one movement's length (a DS step), shape (3,)."""
        ...

    def move_by(self, displacement: ArrayLike) -> MoveResult:
        """Any displacement, shape (3,) (a demonstrator's or a teleoperator's move)."""
        ...

    def observe_effect(self, since: str = "step", source: str | None = None) -> str:
        """The effect since the start of the last movement or of the episode."""
        ...

    def context(self, source: str | None = None) -> Context:
        """Low-level states of every object and the high-level states."""
        ...

    def perturb(self, kind: str, **params: Any) -> None:
        """A perturbation between two steps (``move_object``, ``hold``...)."""
        ...

    @property
    def step_length(self) -> float:
        """Length of one discrete movement (m)."""
        ...

    @property
    def object_names(self) -> tuple[str, ...]:
        """Every object (present or removed)."""
        ...

    @property
    def movable_names(self) -> tuple[str, ...]:
        """The objects a push can move (not the button)."""
        ...

    @property
    def state_names(self) -> tuple[str, ...]:
        """The high-level states."""
        ...

    def close(self) -> None:
        """Release the scene's resources."""
        ...


class ArmSceneProtocol(SceneProtocol, Protocol):
    """A PyBullet scene (:class:`a2l.sim.bullet.BulletScene`): an arm with a gripper,
    cameras, simulated time."""

    #: The acting arm's C++ kinematics.
    kinematics: Any
    #: The robot (:class:`a2l.robot.RobotEntry`) the scene was built with.
    robot_entry: Any

    @property
    def sim_time(self) -> float:
        """Simulated time since the scene was built (s)."""
        ...

    @property
    def client(self) -> int:
        """The PyBullet physics client."""
        ...

    def open_gripper(self) -> None:
        """Open the gripper (high-level state ``gripper``)."""
        ...

    def close_gripper(self) -> None:
        """Close the gripper."""
        ...

    def render(self, camera: int = 0) -> tuple[NDArray[np.uint8], NDArray[np.float32]]:
        """One frame: RGB (H, W, 3) and depth (H, W)."""
        ...

    def place_arm(self, eef: ArrayLike) -> None:
        """Put the arm (kinematically) with its gripper down at `eef`, shape (3,)."""
        ...

    def settle(self, seconds: float = 0.2) -> None:
        """Let the world run without commanding the arm."""
        ...

    def joint_positions(self) -> NDArray[np.float64]:
        """Joint positions of the acting arm, shape (7,)."""
        ...

    def follow_joint_trajectory(self, times: ArrayLike, positions: ArrayLike) -> float:
        """Follow a joint trajectory; seconds simulated."""
        ...

    def other_joint_positions(self) -> dict[str, float]:
        """Positions of the joints outside the acting arm, by name."""
        ...

    def obstacle_boxes(self) -> list[tuple[str, NDArray[np.float64], NDArray[np.float64]]]:
        """Everything but the robot as boxes: ``(name, centre (3,), half extents (3,))`` (m)."""
        ...
