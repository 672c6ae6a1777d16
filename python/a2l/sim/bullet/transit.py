"""What the transit planner (:mod:`a2l.planning.transit`) reads from a PyBullet scene: the
robot's body and joints, and everything else as boxes."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from a2l.sim._pybullet import p
from a2l.sim.bodies import BodyCache
from a2l.sim.bullet.build import SceneObject

__all__ = ["TransitMixin"]


class TransitMixin:
    """The transit view of a :class:`~a2l.sim.bullet.BulletScene` (one of its bases)."""

    _client: int
    _robot: int
    _arm: list[int]
    _floor_z: float
    _movable: list[int]
    _joint_index: dict[str, int]
    _link_index: dict[str, int]
    _bodies: BodyCache
    _objects: dict[str, SceneObject]
    _removed: set[str]
    config: Any

    @property
    def robot(self) -> int:
        """PyBullet body id of the robot."""
        return self._robot

    @property
    def arm_joints(self) -> list[int]:
        """PyBullet joint indices of the acting arm, base to tip (kinematics' order)."""
        return list(self._arm)

    def link_poses(self) -> dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]]:
        """Every link of the robot in the world frame: ``{name: (position (3,), quaternion
        (4,) x, y, z, w)}`` (a recording's link frames)."""
        names = sorted(self._link_index, key=self._link_index.__getitem__)
        states = p.getLinkStates(self._robot, [self._link_index[n] for n in names],
                                 physicsClientId=self._client)
        return {n: (np.asarray(st[4], dtype=float), np.asarray(st[5], dtype=float))
                for n, st in zip(names, states, strict=True)}

    def other_joint_positions(self) -> dict[str, float]:
        """Positions of the robot's movable joints outside the acting arm, by URDF name."""
        names = {j: n for n, j in self._joint_index.items()}
        return {names[j]: float(p.getJointState(self._robot, j, physicsClientId=self._client)[0])
                for j in self._movable if j not in self._arm}

    def obstacle_boxes(self) -> list[tuple[str, NDArray[np.float64], NDArray[np.float64]]]:
        """Everything but the robot as axis-aligned boxes, from PyBullet's current state.

        Returns
        -------
        list of (str, ndarray (3,), ndarray (3,))
            Name, centre and half-extents (m) of the table top, of every object (the
            button's housing and cap, the lamp...) and of the floor.
        """
        c = self._client
        floor = np.array([0.0, 0.0, self._floor_z - 0.05])
        out = [("floor", floor, np.array([3.0, 3.0, 0.05]))]
        ids = self._bodies.ids  # rebuilt at every reset: read the current ids
        bodies = [("table", ids["table"], [-1])]
        bodies += [(o.name, o.body, list(range(-1, p.getNumJoints(o.body, physicsClientId=c))))
                   for o in self._objects.values() if o.name not in self._removed]
        if "lamp" in ids:
            bodies.append(("lamp", ids["lamp"], [-1]))
        for name, body, links in bodies:
            for link in links:
                if link >= 0 and p.getCollisionShapeData(body, link, physicsClientId=c) == ():
                    continue
                lo, hi = (np.asarray(v, dtype=float)
                          for v in p.getAABB(body, link, physicsClientId=c))
                label = name if link < 0 else f"{name}_{link}"
                out.append((label, (lo + hi) / 2, np.maximum((hi - lo) / 2, 1e-4)))
        return out

