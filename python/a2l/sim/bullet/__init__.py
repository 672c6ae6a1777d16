"""The PyBullet scenes: Baxter on its pedestal, a table, and the scene's objects.

Use :func:`a2l.sim.make_scene`. The package holds one concept per module:

- :mod:`~a2l.sim.bullet.build`: building the world (floor, table, Baxter, boxes);
- :mod:`~a2l.sim.bullet.motion`: moving the arm and the gripper (straight lines through the
  C++ IK, joint trajectories, settling);
- :mod:`~a2l.sim.bullet.transit`: what the transit planner reads (obstacles, joints);
- :mod:`~a2l.sim.bullet.base`: :class:`BulletScene`, the reset, the objects and perception;
- :mod:`~a2l.sim.bullet.scenes`: the ``push``, ``grasp`` and ``press`` scenes.
"""

from __future__ import annotations

from a2l.robot.gripper import GRIPPER_DOWN
from a2l.sim.bullet.base import BulletScene
from a2l.sim.bullet.scenes import GraspScene, PressScene, PushScene

__all__ = ["BulletScene", "GraspScene", "PressScene", "PushScene", "GRIPPER_DOWN"]
